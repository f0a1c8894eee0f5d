"""The base's physics: MuJoCo steps the model of `model.py`; this class sets the wheel speeds
and reads the ground truth and the wheels' angles. Plain Python over MuJoCo, no ROS.

Deterministic: MuJoCo steps single-threaded, so the same commands give bit-identical states.
"""

from __future__ import annotations

import math

from turtle_traj.base.model import BaseSpec, mjcf

INSTALL_HINT = ("the physics base needs MuJoCo: pip install 'turtle_traj[physics]' (or pip "
                "install mujoco; make setup installs it)")


SETTLE_S = 0.5  # before time 0: standing still, the base comes to rest in a tenth of this


class MujocoMissing(RuntimeError):
    """MuJoCo is not installed; the message says how to get it."""


def load_mujoco():
    """The mujoco module. :raises MujocoMissing: it is not installed."""
    try:
        import mujoco
    except ImportError as error:
        raise MujocoMissing(f'{INSTALL_HINT} ({error})') from None
    return mujoco


class DiffDrivePhysics:
    """One base on a floor: `drive` sets the wheel speeds, `advance` runs the physics."""

    def __init__(self, spec: BaseSpec) -> None:
        """:raises MujocoMissing: no MuJoCo. :raises ValueError: `spec` has problems."""
        if problems := spec.problems():
            raise ValueError('; '.join(problems))
        self._mujoco = load_mujoco()
        self.spec = spec
        self._model = self._mujoco.MjModel.from_xml_string(mjcf(spec))
        self._data = self._mujoco.MjData(self._model)
        self._mujoco.mj_forward(self._model, self._data)
        joint = self._model.joint
        self._wheel_qpos = [joint(f'{side}_wheel_joint').qposadr[0] for side in ('left', 'right')]
        self._wheel_dof = [joint(f'{side}_wheel_joint').dofadr[0] for side in ('left', 'right')]
        self._setpoints = (0.0, 0.0)  # the motors' speed setpoints now
        self._targets = (0.0, 0.0)  # where `advance` takes them
        self._settle()

    def _settle(self) -> None:
        """Let the base come to rest on its tyres and caster (they sink a fraction of a
        millimetre into the floor), then start the clock: time 0 finds it standing still, at
        the origin, its wheels at angle 0."""
        for _ in range(round(SETTLE_S / self.spec.timestep)):
            self._mujoco.mj_step(self._model, self._data)
        data = self._data
        data.time = 0.0
        data.qpos[0:2] = 0.0
        data.qpos[self._wheel_qpos] = 0.0
        data.qvel[:] = 0.0
        self._mujoco.mj_forward(self._model, data)

    @property
    def time_s(self) -> float:
        return float(self._data.time)

    def drive(self, left_rad_s: float, right_rad_s: float) -> None:
        """The wheel speeds to reach by the end of the next `advance`: the motors' setpoints
        ramp there linearly, step by step, as a motor driver's velocity profile does (a
        setpoint that jumped would jerk the base, and tip it onto its nose when braking)."""
        self._targets = (left_rad_s, right_rad_s)

    def advance(self, duration_s: float) -> None:
        """Step the physics for `duration_s` (a whole number of steps)."""
        steps = round(duration_s / self.spec.timestep)
        (left0, right0), (left1, right1) = self._setpoints, self._targets
        ctrl = self._data.ctrl
        for step in range(1, steps + 1):
            share = step / steps
            ctrl[0] = left0 + (left1 - left0) * share
            ctrl[1] = right0 + (right1 - right0) * share
            self._mujoco.mj_step(self._model, self._data)
        self._setpoints = self._targets

    def pose(self) -> tuple[float, float, float]:
        """The true pose on the floor: x, y [m] and yaw [rad]."""
        qpos = self._data.qpos
        w, z = qpos[3], qpos[6]
        x_axis_x = 1.0 - 2.0 * (qpos[5] ** 2 + z * z)
        x_axis_y = 2.0 * (qpos[4] * qpos[5] + w * z)
        return float(qpos[0]), float(qpos[1]), math.atan2(x_axis_y, x_axis_x)

    def twist(self) -> tuple[float, float]:
        """The true forward speed [m/s] and turn rate [rad/s]."""
        qvel = self._data.qvel  # free joint: world-frame linear, then body-frame angular
        _x, _y, yaw = self.pose()
        forward = qvel[0] * math.cos(yaw) + qvel[1] * math.sin(yaw)
        return float(forward), float(qvel[5])

    def wheel_angles(self) -> tuple[float, float]:
        """How far each wheel has turned since the start [rad], left then right."""
        qpos = self._data.qpos
        return float(qpos[self._wheel_qpos[0]]), float(qpos[self._wheel_qpos[1]])

    def wheel_speeds(self) -> tuple[float, float]:
        qvel = self._data.qvel
        return float(qvel[self._wheel_dof[0]]), float(qvel[self._wheel_dof[1]])

    def height(self) -> float:
        """The body frame's height above the floor [m]: near 0 while the base stands."""
        return float(self._data.qpos[2])
