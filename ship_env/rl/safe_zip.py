"""Reading a stable-baselines3 ``model.zip`` without running any of its code.

SB3 saves an agent as a zip: ``data``, a JSON document of the algorithm's attributes, and one
``<name>.pth`` state dict per network and optimiser. The attributes JSON cannot hold (the spaces,
the policy class, schedules, buffers) are base64 pickles under ``:serialized:``, and unpickling
one runs whatever its author put in it. Beside each pickle SB3 writes readable fields: the object's
type (``:type:``) and its attributes, as JSON or as their printed form. A policy is rebuilt from
those and from the pickles' *opcodes*, which :mod:`pickletools` reads without executing any:

- the observation and action spaces from their readable fields (:data:`SPACE_READERS`): a ``Box``
  from ``dtype``, ``_shape``, ``low`` and ``high`` (the bounds as numpy prints them: exact for
  bounds of up to 8 decimals, such as every ship_env environment's), ship_env's continuous action space
  (:class:`~ship_env.envs.uniform_box.UniformBox`) from the same fields, a ``Discrete`` from ``n`` and
  ``start``; the pickle beside them must refer only to that space's class and numpy's arrays and
  random generators (:data:`NUMPY_PICKLE_GLOBALS`), so what is read is what SB3 would unpickle;
- the policy class from its pickle, which must be one reference to a class of
  :data:`POLICY_CLASSES` and nothing else (a class defined in a script is pickled by value: refused);
- the policy's keyword arguments as JSON, or where one is a class (``activation_fn=nn.Tanh``) from
  its printed form ``<class 'torch.nn.modules.activation.Tanh'>``, a class of :data:`KEYWORD_CLASSES`;
- the weights and optimiser states with ``torch.load(..., weights_only=True)``, which reads tensors
  and plain containers only.

Anything else raises :class:`UnreadableEntry`, naming the entry and what it lacks.
"""

from __future__ import annotations

import base64
import binascii
import importlib
import json
import math
import pickletools
import re
import zipfile
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import PurePosixPath
from typing import Any

import numpy as np
import torch
from gymnasium import spaces

from ship_env.envs.uniform_box import UniformBox

#: The policy classes a policy file may name: ship_env's (:mod:`ship_env.rl.features`), SB3's
#: (PPO and A2C, SAC, TD3, DQN) and sb3-contrib's RecurrentPPO's.
POLICY_CLASSES = frozenset(
    {
        "ship_env.rl.features.ScaledObservationPolicy",
        "ship_env.rl.features.MirroredObservationPolicy",
        "ship_env.rl.features.ScaledObservationLstmPolicy",
        "stable_baselines3.common.policies.ActorCriticPolicy",
        "stable_baselines3.sac.policies.SACPolicy",
        "stable_baselines3.td3.policies.TD3Policy",
        "stable_baselines3.dqn.policies.DQNPolicy",
        "sb3_contrib.common.recurrent.policies.RecurrentActorCriticPolicy",
    }
)
#: The classes a policy's keyword arguments may hold: activations, optimisers, features extractors.
KEYWORD_CLASSES = frozenset(
    {
        *(f"torch.nn.modules.activation.{name}" for name in ("ReLU", "Tanh", "ELU", "LeakyReLU", "GELU", "SiLU")),
        *(f"torch.optim.{module}.{name}" for module, name in (("adam", "Adam"), ("adamw", "AdamW"), ("sgd", "SGD"))),
        "torch.optim.rmsprop.RMSprop",
        "stable_baselines3.common.sb2_compat.rmsprop_tf_like.RMSpropTFLike",
        "stable_baselines3.common.torch_layers.FlattenExtractor",
        "ship_env.rl.features.ScaledObservation",
    }
)
#: What a pickled space may refer to besides its class: numpy's dtypes, arrays and scalars, and the
#: random generator a space carries (numpy 1 names its core ``numpy.core``, numpy 2 ``numpy._core``).
NUMPY_PICKLE_GLOBALS = frozenset(
    {
        "numpy.dtype",
        "numpy.ndarray",
        *(
            f"numpy.{core}.{name}"
            for core in ("core", "_core")
            for name in ("numeric._frombuffer", "multiarray.scalar", "multiarray._reconstruct")
        ),
        "numpy.random._pickle.__generator_ctor",
        "numpy.random._pickle.__bit_generator_ctor",
        "numpy.random._pcg64.PCG64",
        "numpy.random.bit_generator.__pyx_unpickle_SeedSequence",
        "numpy.random.bit_generator.SeedSequence",
    }
)
#: Opcodes of a pickle that is one reference to a global and nothing else (no call, no state).
_REFERENCE_OPCODES = frozenset(
    {"PROTO", "FRAME", "SHORT_BINUNICODE", "BINUNICODE", "UNICODE", "MEMOIZE", "BINPUT", "PUT", "LONG_BINPUT"}
    | {"GLOBAL", "STACK_GLOBAL", "STOP"}
)
_PRINTED_CLASS = re.compile(r"<class '([\w.]+)'>")
_MARK = object()


class UnreadableEntry(ValueError):
    """An entry of ``data`` (or a file of the zip) that cannot be read without running code."""


@dataclass(frozen=True)
class SavedPolicy:
    """What rebuilds a saved policy network (the weights aside).

    Attributes:
        policy_class: the policy's class.
        policy_kwargs: the keyword arguments it was built with (its config's ``policy_kwargs``).
        observation_space, action_space: the spaces it was trained with.
        use_sde: whether it explores with state-dependent noise (SB3's ``use_sde``).
    """

    policy_class: type
    policy_kwargs: dict[str, Any]
    observation_space: spaces.Space
    action_space: spaces.Space
    use_sde: bool


def pickled_globals(entry: str, pickled: bytes) -> list[str]:
    """``module.name`` of every global (class or function) the pickle refers to: what unpickling it
    would import and may call. Read from its opcodes, none executed; a name built at run time reads ``?``."""
    stack: list[Any] = []
    memo: dict[int, Any] = {}
    found = []
    try:
        for opcode, opcode_argument, _ in pickletools.genops(pickled):
            argument: Any = opcode_argument
            if opcode.name == "MEMOIZE":
                memo[len(memo)] = stack[-1]
            elif opcode.name in ("PUT", "BINPUT", "LONG_BINPUT"):
                memo[argument] = stack[-1]
            elif opcode.name in ("GET", "BINGET", "LONG_BINGET"):
                stack.append(memo[argument])
            elif opcode.name == "STACK_GLOBAL":
                module, name = stack.pop(-2), stack.pop()
                found.append(f"{module}.{name}" if isinstance(module, str) and isinstance(name, str) else "?")
                stack.append(None)
            else:
                if opcode.name in ("GLOBAL", "INST"):  # their argument is "module name"
                    found.append(argument.replace(" ", "."))
                elif opcode.name.startswith("EXT"):  # a global by its copyreg extension code
                    found.append("?")
                before = opcode.stack_before
                if pickletools.markobject in before:
                    while stack.pop() is not _MARK:
                        pass
                    before = before[: before.index(pickletools.markobject)]
                del stack[len(stack) - len(before) :]
                constant = argument if opcode.stack_after == [pickletools.pyunicode] else None  # a str, kept
                stack += [_MARK if kind is pickletools.markobject else constant for kind in opcode.stack_after]
    except (ValueError, IndexError, KeyError) as error:
        raise UnreadableEntry(f"{entry}: not a pickle ({error})") from None
    return found


def _pickle_of(name: str, entry: Mapping[str, Any]) -> bytes:
    try:
        return base64.b64decode(entry[":serialized:"], validate=True)
    except (KeyError, TypeError, binascii.Error):
        raise UnreadableEntry(f"{name}: no base64 ':serialized:' field") from None


def _check_globals(name: str, entry: Mapping[str, Any], allowed: frozenset[str], made_of: str) -> None:
    """:class:`UnreadableEntry` if the entry's pickle refers to a global outside ``allowed``."""
    for reference in pickled_globals(name, _pickle_of(name, entry)):
        if reference not in allowed:
            raise UnreadableEntry(f"{name}: its pickle refers to {reference}, which is not {made_of}")


def import_allowed(name: str, allowed: frozenset[str], what: str) -> type:
    """The class ``module.Name`` if ``allowed`` holds it; :class:`UnreadableEntry` if not."""
    if name not in allowed:
        raise UnreadableEntry(f"{what} {name} is not among the allowed ones ({', '.join(sorted(allowed))})")
    module, _, attribute = name.rpartition(".")
    found: type = getattr(importlib.import_module(module), attribute)
    return found


def _field(name: str, entry: Mapping[str, Any], key: str) -> Any:
    if key not in entry:
        raise UnreadableEntry(f"{name}: no readable '{key}' field")
    return entry[key]


def _printed_array(name: str, text: Any, shape: tuple[int, ...], dtype: np.dtype) -> np.ndarray:
    """An array of ``shape`` from numpy's printed form (``'[-1. -4.  0.]'``, nested brackets for more axes)."""
    tokens = str(text).replace("[", " ").replace("]", " ").split()
    try:
        values = [float(token) for token in tokens]
    except ValueError:
        values = []
    if "..." in str(text) or len(values) != math.prod(shape):
        raise UnreadableEntry(f"{name}: its printed form {text!r} does not give {math.prod(shape)} numbers")
    return np.asarray(values).reshape(shape).astype(dtype)


def _box(name: str, entry: Mapping[str, Any]) -> spaces.Box:
    dtype = np.dtype(str(_field(name, entry, "dtype")))
    shape = tuple(int(size) for size in _field(name, entry, "_shape"))
    low = _printed_array(f"{name}.low", _field(name, entry, "low"), shape, dtype)
    high = _printed_array(f"{name}.high", _field(name, entry, "high"), shape, dtype)
    return spaces.Box(low, high, shape, dtype)


def _uniform_box(name: str, entry: Mapping[str, Any]) -> UniformBox:
    box = _box(name, entry)
    low, high = box.low.flat[0], box.high.flat[0]
    if not (np.all(box.low == low) and np.all(box.high == high)):
        raise UnreadableEntry(f"{name}: a UniformBox whose bounds are not one value each: {box}")
    return UniformBox(float(low), float(high), box.shape, box.dtype)


def _discrete(name: str, entry: Mapping[str, Any]) -> spaces.Discrete:
    return spaces.Discrete(int(_field(name, entry, "n")), start=int(_field(name, entry, "start")))


#: The spaces read from their readable fields: their ``:type:`` -> (their class, reader).
SPACE_READERS: dict[str, tuple[str, Callable[[str, Mapping[str, Any]], spaces.Space]]] = {
    "<class 'gymnasium.spaces.box.Box'>": ("gymnasium.spaces.box.Box", _box),
    "<class 'ship_env.envs.uniform_box.UniformBox'>": ("ship_env.envs.uniform_box.UniformBox", _uniform_box),
    "<class 'gymnasium.spaces.discrete.Discrete'>": ("gymnasium.spaces.discrete.Discrete", _discrete),
}


def read_space(name: str, entry: Any) -> spaces.Space:
    """The space a ``data`` entry holds, from its readable fields (:data:`SPACE_READERS`)."""
    if not isinstance(entry, dict):
        raise UnreadableEntry(f"{name}: not a saved space")
    kind = entry.get(":type:")
    if kind not in SPACE_READERS:
        raise UnreadableEntry(f"{name}: a {kind} is not read without its code (only {', '.join(SPACE_READERS)})")
    space_class, reader = SPACE_READERS[kind]
    _check_globals(name, entry, NUMPY_PICKLE_GLOBALS | {space_class}, f"part of a {space_class}")
    try:
        return reader(name, entry)
    except (TypeError, ValueError) as error:
        raise UnreadableEntry(f"{name}: {error}") from None


def read_policy_class(entry: Any) -> type:
    """The class the ``policy_class`` entry's pickle refers to, which must be in :data:`POLICY_CLASSES`."""
    if not isinstance(entry, dict):
        raise UnreadableEntry("policy_class: not a saved class")
    pickled = _pickle_of("policy_class", entry)
    references = pickled_globals("policy_class", pickled)
    opcodes = {opcode.name for opcode, _, _ in pickletools.genops(pickled)}
    if len(references) != 1 or not opcodes <= _REFERENCE_OPCODES:
        raise UnreadableEntry(
            f"policy_class: its pickle is not one reference to a class (it refers to {', '.join(references) or 'none'}"
            f" and uses {', '.join(sorted(opcodes - _REFERENCE_OPCODES)) or 'no other opcode'})"
        )
    return import_allowed(references[0], POLICY_CLASSES, "policy_class: the class")


def read_policy_kwargs(entry: Any) -> dict[str, Any]:
    """The policy's keyword arguments: JSON as saved, or a pickled dict's readable fields, where a
    class is printed ``<class 'module.Name'>`` (one of :data:`KEYWORD_CLASSES`)."""
    if entry is None:
        return {}
    if not isinstance(entry, dict):
        raise UnreadableEntry("policy_kwargs: not a dict")
    if ":serialized:" not in entry:
        return dict(entry)
    if entry.get(":type:") != "<class 'dict'>":
        raise UnreadableEntry(f"policy_kwargs: a {entry.get(':type:')}, not a dict")
    _check_globals("policy_kwargs", entry, KEYWORD_CLASSES, "an allowed keyword class")
    kwargs = {}
    for key, value in entry.items():
        if key.startswith(":"):
            continue
        printed_class = _PRINTED_CLASS.fullmatch(value) if isinstance(value, str) else None
        if printed_class is not None:
            value = import_allowed(printed_class[1], KEYWORD_CLASSES, f"policy_kwargs.{key}: the class")
        elif isinstance(value, str) and value[:1] in "<{[(":
            raise UnreadableEntry(f"policy_kwargs.{key}: {value!r} is an object printed, not readable without its code")
        kwargs[key] = value
    return kwargs


def read_saved_policy(archive: zipfile.ZipFile) -> SavedPolicy:
    """The policy's class, keyword arguments and spaces from the zip's ``data``, nothing unpickled."""
    if "data" not in archive.namelist():
        raise UnreadableEntry("no 'data' file")
    try:
        data = json.loads(archive.read("data"))
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise UnreadableEntry(f"data: not JSON ({error})") from None
    if not isinstance(data, dict):
        raise UnreadableEntry("data: not a JSON object of the agent's attributes")
    missing = [key for key in ("policy_class", "observation_space", "action_space") if key not in data]
    if missing:
        raise UnreadableEntry(f"data: no {', '.join(missing)}")
    return SavedPolicy(
        policy_class=read_policy_class(data["policy_class"]),
        policy_kwargs=read_policy_kwargs(data.get("policy_kwargs")),
        observation_space=read_space("observation_space", data["observation_space"]),
        action_space=read_space("action_space", data["action_space"]),
        use_sde=data.get("use_sde") is True,
    )


def read_state_dicts(archive: zipfile.ZipFile) -> dict[str, Any]:
    """Every ``<name>.pth`` state dict of the zip (``policy``, ``policy.optimizer``, ...) by name, read
    with ``torch.load(..., weights_only=True)``; ``pytorch_variables.pth`` (not a state dict) left out."""
    state_dicts = {}
    for file_name in archive.namelist():
        path = PurePosixPath(file_name)
        if path.suffix != ".pth" or file_name == "pytorch_variables.pth":
            continue
        with archive.open(file_name) as stream:
            try:
                state_dicts[path.stem] = torch.load(stream, map_location="cpu", weights_only=True)
            except Exception as error:  # torch's UnpicklingError names what weights_only refused
                raise UnreadableEntry(f"{file_name}: not tensors alone ({error})") from None
    return state_dicts
