"""The uncertainty of a least-squares fit from its Jacobian: (J^T J)^-1, infinite where the data say nothing.

The output-error fit (:mod:`.fit`) scales it by s^2 = |residual|^2 / (m - n), the Gauss-Newton estimate
at the optimum, for its terms' covariance and standard errors.
"""

from __future__ import annotations

import math

import numpy as np

#: Share of an unknown's unit vector in the Jacobian's null space above which the data do not determine it
#: (a singular vector's rounding error is of order sqrt(eps) where singular values lie close).
NULL_SHARE = 1e-8


def unknown_variances(jacobian: np.ndarray) -> np.ndarray:
    """The diagonal of (J^T J)^-1, infinite for an unknown the data do not determine (:func:`unknown_covariance`)."""
    return np.diag(unknown_covariance(jacobian)).copy()


def unknown_covariance(jacobian: np.ndarray) -> np.ndarray:
    """(J^T J)^-1, with infinite rows and columns for the unknowns the data do not determine.

    From the singular value decomposition J = U S V^T: singular values below s_max max(m, n) eps
    (numpy's rank rule) count as zero, and their right singular vectors span the null space, the
    directions no residual sees. An unknown whose unit vector has a share above ``NULL_SHARE`` in
    that space (a term that moves nothing, or only as another does) is not determined: infinite
    variance, never the pseudo-inverse's 0. The others get sum_k V_jk V_lk / s_k^2 over the rest.
    """
    if jacobian.shape[1] == 0:
        return np.zeros((0, 0))
    _, singular, right = np.linalg.svd(jacobian, full_matrices=False)  # singular values in falling order
    tolerance = (singular[0] if len(singular) else 0.0) * max(jacobian.shape) * np.finfo(float).eps
    rank = int(np.count_nonzero(singular > tolerance))
    null_share = 1.0 - np.sum(right[:rank] ** 2, axis=0)  # V's rows are orthonormal: the rest is the null space
    determined = right[:rank] / singular[:rank, np.newaxis]
    covariance = determined.T @ determined
    undetermined = null_share > NULL_SHARE
    covariance[undetermined, :] = math.inf
    covariance[:, undetermined] = math.inf
    return covariance
