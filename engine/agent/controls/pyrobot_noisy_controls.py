"""Habitat's noisy PyRobot controls: moves and turns with the actuation noise of real robots.

The noise models are those PyRobot measured on the LoCoBot and LoCoBot-Lite with three
controllers (ILQR, Proportional, Movebase), as Habitat-sim ships them (``habitat_sim.agent.
controls.pyrobot_noisy_controls``; please cite PyRobot, https://pyrobot.org, if you use them).
Each motion has two independent truncated Gaussians with diagonal covariance:

* ``linear`` ``(2,)``: noise along the intended direction and across it, meters;
* ``rotation`` ``(1,)``: noise of the heading, radians.

One noisy action (``_noisy_action``), for a node with rotation ``R`` (columns: local axes in the
parent frame), intended translation ``a`` (m) and rotation ``theta`` (degrees), multiplier ``k``::

    n_t ~ k * N_trunc(mu_lin, sigma_lin)       (a move: n_t[0] >= -0.95 |a|)
    n_r ~ k * N_trunc(mu_rot, sigma_rot)       (a turn: n_r >= -0.95 |theta| in radians)
    both signed by sign(a + 1e-8), sign(theta + 1e-8): moves and turns overshoot on average
    node.translate_local(-R[:, 2] (a + n_t[0]) + R[:, 0] n_t[1])
    node.rotate_y_local(theta degrees + n_r radians);  rotation normalized

Every Gaussian is truncated at 3 standard deviations. The offset goes through
``translate_local`` with parent-frame axes, exactly as Habitat does (a TRS node adds a
``translate_local`` vector in the parent frame, see ``engine.scene.graph``). Samples come
from one ``numpy.random.RandomState``, seeded by ``Simulator.seed(n)`` and the
configuration's ``random_seed`` (``seed_noise``): the same seed gives the same noisy
trajectory.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.stats

from engine import mn
from engine.agent.controls.controls import ActuationSpec, SceneNodeControl
from engine.agent.controls.registry import registry
from engine.scene.graph import SceneNode

__all__ = [
    "MotionNoiseModel",
    "ControllerNoiseModel",
    "RobotNoiseModel",
    "PyRobotNoisyActuationSpec",
    "pyrobot_noise_models",
    "seed_noise",
]

TRUNCATION_SIGMAS = 3.0  # every Gaussian is cut at +-3 standard deviations
_noise_random = np.random.RandomState()


def seed_noise(seed: int) -> None:
    """Seed the generator every noisy control draws from (``Simulator.seed`` calls it)."""
    _noise_random.seed(seed)


class TruncatedDiagonalGaussian:
    """A Gaussian with diagonal covariance, each component truncated at 3 sigma (or tighter)."""

    def __init__(self, mean: list[float], variance: list[float]) -> None:
        self.mean = np.array(mean, dtype=np.float64)
        self.cov = np.diag(np.array(variance, dtype=np.float64))

    def sample(self, lower: list[float | None] | None = None) -> np.ndarray:
        """One sample; ``lower[i]`` (optional) raises the lower bound of component ``i``."""
        sample = np.zeros_like(self.mean)
        for i, mean in enumerate(self.mean):
            std = float(np.sqrt(self.cov[i, i]))
            a, b = -TRUNCATION_SIGMAS, TRUNCATION_SIGMAS
            if lower is not None and lower[i] is not None and std > 0:
                a = max((float(lower[i]) - mean) / std, a)  # type: ignore[arg-type]
            if std == 0.0:
                sample[i] = mean
                continue
            sample[i] = scipy.stats.truncnorm.rvs(a, b, mean, std, random_state=_noise_random)
        return sample


@dataclass(frozen=True)
class MotionNoiseModel:
    linear: TruncatedDiagonalGaussian
    rotation: TruncatedDiagonalGaussian


@dataclass(frozen=True)
class ControllerNoiseModel:
    linear_motion: MotionNoiseModel
    rotational_motion: MotionNoiseModel


@dataclass(frozen=True)
class RobotNoiseModel:
    ILQR: ControllerNoiseModel
    Proportional: ControllerNoiseModel
    Movebase: ControllerNoiseModel

    def __getitem__(self, key: str) -> ControllerNoiseModel:
        if key not in CONTROLLERS:
            raise KeyError(f"{key!r} is not a known controller; known: {list(CONTROLLERS)}")
        return getattr(self, key)


def _model(lin_mean, lin_var, rot_mean, rot_var) -> MotionNoiseModel:
    return MotionNoiseModel(
        TruncatedDiagonalGaussian(lin_mean, lin_var), TruncatedDiagonalGaussian(rot_mean, rot_var)
    )


CONTROLLERS = ("ILQR", "Proportional", "Movebase")
#: robot -> controller -> (linear motion, rotational motion): PyRobot's measured means/variances
pyrobot_noise_models = {
    "LoCoBot": RobotNoiseModel(
        ILQR=ControllerNoiseModel(
            _model([0.014, 0.009], [0.006, 0.005], [0.008], [0.004]),
            _model([0.003, 0.003], [0.002, 0.003], [0.023], [0.012]),
        ),
        Proportional=ControllerNoiseModel(
            _model([0.017, 0.042], [0.007, 0.023], [0.031], [0.026]),
            _model([0.001, 0.005], [0.001, 0.004], [0.043], [0.017]),
        ),
        Movebase=ControllerNoiseModel(
            _model([0.074, 0.036], [0.019, 0.033], [0.189], [0.038]),
            _model([0.002, 0.003], [0.0, 0.002], [0.219], [0.019]),
        ),
    ),
    "LoCoBot-Lite": RobotNoiseModel(
        ILQR=ControllerNoiseModel(
            _model([0.142, 0.023], [0.008, 0.008], [0.031], [0.028]),
            _model([0.002, 0.002], [0.001, 0.002], [0.122], [0.03]),
        ),
        Proportional=ControllerNoiseModel(
            _model([0.135, 0.043], [0.007, 0.009], [0.049], [0.009]),
            _model([0.002, 0.002], [0.002, 0.001], [0.054], [0.061]),
        ),
        Movebase=ControllerNoiseModel(
            _model([0.192, 0.117], [0.055, 0.144], [0.128], [0.143]),
            _model([0.002, 0.001], [0.001, 0.001], [0.173], [0.025]),
        ),
    ),
}


@dataclass
class PyRobotNoisyActuationSpec(ActuationSpec):
    """An actuation with PyRobot noise: ``robot`` (``LoCoBot``, ``LoCoBot-Lite``),
    ``controller`` (``ILQR``, ``Proportional``, ``Movebase``) and ``noise_multiplier``."""

    amount: float = 0.0
    robot: str = "LoCoBot"
    controller: str = "ILQR"
    noise_multiplier: float = 1.0

    def __post_init__(self) -> None:
        if self.robot not in pyrobot_noise_models:
            raise ValueError(f"{self.robot!r} is not a known robot: {list(pyrobot_noise_models)}")
        if self.controller not in CONTROLLERS:
            raise ValueError(f"{self.controller!r} is not a known controller: {CONTROLLERS}")

    def motion(self, kind: str) -> MotionNoiseModel:
        """The noise model of a ``"linear"`` or ``"rotational"`` motion."""
        controller = pyrobot_noise_models[self.robot][self.controller]
        return controller.linear_motion if kind == "linear" else controller.rotational_motion


def _noisy_action(
    node: SceneNode,
    translate: float,
    rotate_degrees: float,
    spec: PyRobotNoisyActuationSpec,
    kind: str,
) -> None:
    """Move/turn ``node`` with noise (``kind`` ``"linear"`` or ``"rotational"``; the module
    docstring has the equations)."""
    model, k = spec.motion(kind), float(spec.noise_multiplier)
    lower = [-0.95 * abs(translate), None] if kind == "linear" else None
    translation_noise = k * model.linear.sample(lower) * np.sign(translate + 1e-8)
    axes = mn.quaternion_to_matrix(node.rotation.xyzw)  # columns: local axes, parent frame
    node.translate_local(
        -axes[:, 2] * (translate + translation_noise[0]) + axes[:, 0] * translation_noise[1]
    )
    turn_lower = [-0.95 * abs(np.deg2rad(rotate_degrees))] if kind == "rotational" else None
    rotation_noise = k * model.rotation.sample(turn_lower) * np.sign(rotate_degrees + 1e-8)
    node.rotate_local(mn.Rad(np.deg2rad(rotate_degrees) + float(rotation_noise[0])), (0, 1, 0))
    node.rotation = node.rotation.normalized()


def _checked(spec: ActuationSpec) -> PyRobotNoisyActuationSpec:
    if not isinstance(spec, PyRobotNoisyActuationSpec):
        raise TypeError(f"a pyrobot noisy control needs a PyRobotNoisyActuationSpec, got {spec!r}")
    return spec


@registry.register_move_fn(body_action=True)
class PyrobotNoisyMoveBackward(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        spec = _checked(actuation_spec)
        _noisy_action(scene_node, -float(spec.amount), 0.0, spec, "linear")


@registry.register_move_fn(body_action=True)
class PyrobotNoisyMoveForward(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        spec = _checked(actuation_spec)
        _noisy_action(scene_node, float(spec.amount), 0.0, spec, "linear")


@registry.register_move_fn(body_action=True)
class PyrobotNoisyTurnLeft(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        spec = _checked(actuation_spec)
        _noisy_action(scene_node, 0.0, float(spec.amount), spec, "rotational")


@registry.register_move_fn(body_action=True)
class PyrobotNoisyTurnRight(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        spec = _checked(actuation_spec)
        _noisy_action(scene_node, 0.0, -float(spec.amount), spec, "rotational")
