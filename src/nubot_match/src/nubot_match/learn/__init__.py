"""Training robots on the environments: the tasks, seeded episodes of a policy file, and the trainer.

``tasks`` and ``episodes`` need gymnasium only; ``trainer`` loads Stable-Baselines3 and PyTorch
(requirements-train.txt, installed by ``make train``) when it trains.
"""
