"""A trained policy as a file of numbers, played with numpy alone (a robot needs no learning library).

Requires: numpy. Provides:

- ``ACTION_NAMES`` and ``command_from_action(action, kick_max_speed)``: the action of one learning robot, the
  vector ``[vx, vy, w, dribble, kick]`` (body frame [m/s], [rad/s]; dribble and kick switch on above
  ``TRIGGER``; a kick is a ground pass at ``round(kick * kick_max_speed)`` m/s), as one cycle's ``RobotCommand``.
  The environments (``nubot_match.envs.actions``) and a robot playing a policy in a match use it alike.
- ``DERIVED`` and ``policy_input(values, names, half_length)``: a policy's input vector, from the entries of the
  environment's observation by name, with entries in the robot's own frame derived from them (``derived``): what
  a learner sees while training and a robot in a match alike.
- ``PolicyNet``: a multilayer perceptron with its observation and action layouts, saved as one ``.npz``
  (``save``, ``PolicyNet.load``; no pickled objects). ``act(obs)`` maps the raw observation (entries named
  by ``observations``, clipped into [``obs_low``, ``obs_high``]) linearly onto [-1, 1], runs the layers (tanh
  between them, none after the last), clips the output to [-1, 1] and maps it onto [``act_low``,
  ``act_high``]: a deterministic policy trained on the rescaled spaces (the mean of a Gaussian policy).
  ``PolicyNet.constant`` answers one action whatever it sees.
- ``PolicyError`` for a missing, damaged or inconsistent file, or an observation of the wrong shape.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from nubot_common import NubotCommonError
from nubot_common.commands import BodyVelocity, KickCommand, KickKind, RobotCommand
from nubot_common.geometry import rotate
from nubot_common.untrusted import UntrustedInputError, declared_arrays

Array = NDArray[np.float64]
ACTION_NAMES = ("vx", "vy", "w", "dribble", "kick")
TRIGGER = 0.5  # dribble and kick entries above this switch on
FORMAT = 1  # the file layout written by ``save``
MAX_WEIGHTS = 4_000_000  # numbers in all layers together (a 64 x 64 policy has about 5,000)
ACTIVATIONS = ("tanh", "relu")


# What a robot sees in its own frame (x forward along the kicker, y left), derived from the team-frame entries by
# ``derived``: the ball, the centre of the attacked goal and the opponents' goalie, each as a distance [m] and
# the cosine and sine of its bearing; the ball also as forward and left offsets [m] and its velocity [m/s].
DERIVED_BOUNDS = {"ball_forward": 25.0, "ball_left": 25.0, "ball_distance": 30.0, "ball_cos": 1.0, "ball_sin": 1.0,
                  "ball_vforward": 15.0, "ball_vleft": 15.0, "goal_distance": 30.0, "goal_cos": 1.0,
                  "goal_sin": 1.0, "goalie_distance": 30.0, "goalie_cos": 1.0, "goalie_sin": 1.0}
DERIVED = tuple(DERIVED_BOUNDS)
NEEDED = ("x", "y", "cos_theta", "sin_theta", "ball_dx", "ball_dy", "ball_vx", "ball_vy", "goalie_x", "goalie_y")


def derived(values: Mapping[str, float], half_length: float) -> dict[str, float]:
    """The ``DERIVED`` entries from the team-frame ``values`` (``NEEDED``); the attacked goal's centre is at
    (``half_length``, 0)."""
    heading = math.atan2(values["sin_theta"], values["cos_theta"])

    def body(dx: float, dy: float) -> tuple[float, float]:
        return rotate(dx, dy, -heading)

    out: dict[str, float] = {}
    ball = body(values["ball_dx"], values["ball_dy"])
    out["ball_forward"], out["ball_left"] = ball
    out["ball_vforward"], out["ball_vleft"] = body(values["ball_vx"], values["ball_vy"])
    for name, (dx, dy) in (("ball", (values["ball_dx"], values["ball_dy"])),
                           ("goal", (half_length - values["x"], -values["y"])),
                           ("goalie", (values["goalie_x"] - values["x"], values["goalie_y"] - values["y"]))):
        forward, left = body(dx, dy)
        distance = math.hypot(forward, left)
        out[f"{name}_distance"] = distance
        bearing = (forward / distance, left / distance) if distance > 1e-9 else (1.0, 0.0)
        out[f"{name}_cos"], out[f"{name}_sin"] = bearing
    return out


def policy_input(values: Mapping[str, float], names: Sequence[str], half_length: float) -> Array:
    """The vector of ``names`` from ``values`` (the environment's entries by name), with ``DERIVED`` ones computed."""
    if any(n in DERIVED_BOUNDS for n in names):
        values = {**values, **derived(values, half_length)}
    return np.array([values[n] for n in names], dtype=np.float64)


class PolicyError(NubotCommonError):
    """A policy file that cannot be played, or an observation it cannot take."""


def command_from_action(action: Sequence[float] | Array, kick_max_speed: float) -> RobotCommand:
    """One control cycle's commands for ``action`` = [vx, vy, w, dribble, kick] (already checked finite)."""
    a = [float(v) for v in action]
    kick = a[4] > TRIGGER
    return RobotCommand(
        velocity=BodyVelocity(a[0], a[1], a[2]),
        dribble=a[3] > TRIGGER,
        # A kick takes the held ball: switching the handler off first would drop it before the kick.
        ball_handle=None if kick else int(a[3] > TRIGGER),
        kick=KickCommand(KickKind.GROUND, int(round(a[4] * kick_max_speed))) if kick else None,
    )


@dataclass
class PolicyNet:
    observations: tuple[str, ...]  # the entries of an observation, in order
    obs_low: Array  # float64, per entry
    obs_high: Array
    act_low: Array  # float64, per ACTION_NAMES entry
    act_high: Array
    weights: list[Array]  # layer k: (outputs, inputs)
    biases: list[Array]  # layer k: (outputs,)
    activation: str = "tanh"
    meta: dict[str, Any] = field(default_factory=dict)  # what trained it: env id, task, steps, seed, versions

    def __post_init__(self) -> None:
        self.observations = tuple(self.observations)
        self.obs_low, self.obs_high = (np.asarray(a, dtype=np.float64) for a in (self.obs_low, self.obs_high))
        self.act_low, self.act_high = (np.asarray(a, dtype=np.float64) for a in (self.act_low, self.act_high))
        self.weights = [np.asarray(w, dtype=np.float64) for w in self.weights]
        self.biases = [np.asarray(b, dtype=np.float64) for b in self.biases]
        n = len(self.observations)
        if self.activation not in ACTIVATIONS:
            raise PolicyError(f"activation {self.activation!r} is none of {', '.join(ACTIVATIONS)}")
        if self.obs_low.shape != (n,) or self.obs_high.shape != (n,) or not np.all(self.obs_high > self.obs_low):
            raise PolicyError(f"the observation bounds must be {n} pairs with low < high")
        if self.act_low.shape != (len(ACTION_NAMES),) or self.act_high.shape != (len(ACTION_NAMES),) \
                or not np.all(self.act_high > self.act_low):
            raise PolicyError(f"the action bounds must be {len(ACTION_NAMES)} pairs with low < high")
        if not self.weights or len(self.weights) != len(self.biases):
            raise PolicyError("a policy needs at least one layer, each with its biases")
        inputs = n
        for k, (w, b) in enumerate(zip(self.weights, self.biases)):
            if w.ndim != 2 or w.shape[1] != inputs or b.shape != (w.shape[0],):
                raise PolicyError(f"layer {k} has weights {w.shape} and biases {b.shape}; it takes {inputs} inputs")
            if not (np.all(np.isfinite(w)) and np.all(np.isfinite(b))):
                raise PolicyError(f"layer {k} holds a number that is not finite")
            inputs = w.shape[0]
        if inputs != len(ACTION_NAMES):
            raise PolicyError(f"the last layer gives {inputs} outputs; an action has {len(ACTION_NAMES)}")
        for bound in (self.obs_low, self.obs_high, self.act_low, self.act_high):
            if not np.all(np.isfinite(bound)):
                raise PolicyError("a bound is not finite")

    @classmethod
    def constant(cls, action: Sequence[float], observations: Sequence[str], obs_low: Sequence[float],
                 obs_high: Sequence[float], act_low: Sequence[float], act_high: Sequence[float],
                 **meta: Any) -> PolicyNet:
        """A policy that answers ``action`` whatever it sees (a placeholder, or a test's known driver)."""
        low, high = np.asarray(act_low, dtype=np.float64), np.asarray(act_high, dtype=np.float64)
        bias = 2.0 * (np.asarray(action, dtype=np.float64) - low) / (high - low) - 1.0
        return cls(tuple(observations), np.asarray(obs_low), np.asarray(obs_high), low, high,
                   [np.zeros((len(ACTION_NAMES), len(observations)))], [bias], meta=meta)

    # --- playing --------------------------------------------------------------------------------------
    def act(self, obs: Sequence[float] | Array) -> Array:
        """The action [vx, vy, w, dribble, kick] (float64, within the action bounds) for the raw ``obs``."""
        x = np.asarray(obs, dtype=np.float64)
        if x.shape != self.obs_low.shape:
            raise PolicyError(f"an observation has {len(self.observations)} entries, got shape {x.shape}")
        if not np.all(np.isfinite(x)):
            bad = [self.observations[k] for k in np.flatnonzero(~np.isfinite(x))]
            raise PolicyError(f"observation entries not finite: {', '.join(bad)}")
        x = np.clip(x, self.obs_low, self.obs_high)
        x = 2.0 * (x - self.obs_low) / (self.obs_high - self.obs_low) - 1.0
        last = len(self.weights) - 1
        for k, (w, b) in enumerate(zip(self.weights, self.biases)):
            x = w @ x + b
            if k < last:
                x = np.tanh(x) if self.activation == "tanh" else np.maximum(x, 0.0)
        x = np.clip(x, -1.0, 1.0)
        out: Array = self.act_low + (x + 1.0) * 0.5 * (self.act_high - self.act_low)
        return out

    # --- the file -------------------------------------------------------------------------------------
    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the policy to ``path`` (``.npz``), atomically; the path written."""
        path = Path(path)
        arrays: dict[str, NDArray[Any]] = {
            "format": np.array([FORMAT]), "meta": np.array(json.dumps(self._header(), sort_keys=True)),
            "obs_low": self.obs_low, "obs_high": self.obs_high, "act_low": self.act_low, "act_high": self.act_high}
        for k, (w, b) in enumerate(zip(self.weights, self.biases)):
            arrays[f"w{k}"], arrays[f"b{k}"] = w, b
        partial = path.with_name(path.name + ".partial")
        with open(partial, "wb") as handle:
            np.savez(handle, **arrays)
        os.replace(partial, path)
        return path

    def _header(self) -> dict[str, Any]:
        return {**self.meta, "observations": list(self.observations), "actions": list(ACTION_NAMES),
                "activation": self.activation}

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> PolicyNet:
        """The policy in ``path``; ``PolicyError`` saying what is wrong with a missing or damaged file."""
        path = Path(path)
        if not path.is_file():
            raise PolicyError(f"no policy file {path}")
        try:
            declared = declared_arrays(path)
        except UntrustedInputError as exc:
            raise PolicyError(f"{path} is not a policy file: {exc}") from None
        size = sum(int(np.prod(shape)) for shape, _dtype in declared.values())
        if size > MAX_WEIGHTS:
            raise PolicyError(f"{path} declares {size} numbers, more than a policy's {MAX_WEIGHTS}")
        missing = {"format", "meta", "obs_low", "obs_high", "act_low", "act_high", "w0", "b0"} - set(declared)
        if missing:
            raise PolicyError(f"{path} is not a policy file: it lacks {', '.join(sorted(missing))}")
        try:
            with np.load(path, allow_pickle=False) as data:
                version = int(data["format"][0])
                if version != FORMAT:
                    raise PolicyError(f"{path} is a policy of format {version}; this version reads {FORMAT}")
                header = json.loads(str(data["meta"][()]))
                layers = sum(1 for name in declared if name.startswith("w"))
                weights = [data[f"w{k}"] for k in range(layers)]
                biases = [data[f"b{k}"] for k in range(layers)]
                bounds = [data[n] for n in ("obs_low", "obs_high", "act_low", "act_high")]
        except PolicyError:
            raise
        except Exception as exc:  # noqa: BLE001 - a damaged archive: zip's, zlib's, json's, numpy's errors
            raise PolicyError(f"{path} is not a readable policy file: {type(exc).__name__}: {exc}") from None
        if not isinstance(header, dict) or header.get("actions") != list(ACTION_NAMES) \
                or not isinstance(header.get("observations"), list):
            raise PolicyError(f"{path}: its header names no observations, or actions other than "
                              f"{', '.join(ACTION_NAMES)}")
        names = tuple(str(n) for n in header.pop("observations"))
        header.pop("actions")
        activation = str(header.pop("activation", "tanh"))
        try:
            return cls(names, bounds[0], bounds[1], bounds[2], bounds[3], weights, biases, activation, header)
        except PolicyError as exc:
            raise PolicyError(f"{path}: {exc}") from None
