"""Learned policies: training stable-baselines3 agents on the environments and loading the results.

- :mod:`ship_env.rl.agents`: the hyper-parameters of ``configs/agents/<algo>.yaml``, keyed by
  environment id in rl-zoo3's format (the files load unchanged in rl-zoo3);
- :mod:`ship_env.rl.training`: one training run on the native vector environment, saved as
  ``model.zip`` beside its ``metadata.json`` (:mod:`ship_env.rl.metadata`);
- :mod:`ship_env.rl.policy_file`: a saved policy loaded and checked against the environment it
  is to steer, read without running any code the file carries (:mod:`ship_env.rl.safe_zip`);
  :mod:`ship_env.rl.shipped` lists the policies that ship with the package;
- :mod:`ship_env.rl.cli_train`: ``ship-env train``.
"""
