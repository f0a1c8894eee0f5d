"""A TurtleBot3 Burger-sized differential-drive base as a MuJoCo model (MJCF), from its spec.

Pure data and text: nothing here loads MuJoCo. The published Burger figures are the defaults:
wheel radius 0.033 m, wheel separation 0.160 m, about 1 kg, a ball caster behind the axle, and
its centre of mass 32 mm behind the axle (the Burger's URDF).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

# Where the mass sits: each wheel (tyre and hub) and the caster take these shares, the chassis
# the rest. Chassis: the Burger's 138 mm square plates, its centre of mass 32 mm behind the
# axle (the URDF's) and 70 mm up (the battery rides low); the caster 81 mm behind the axle.
WHEEL_MASS_SHARE = 0.03
CASTER_MASS_SHARE = 0.01
CHASSIS_COM_X_M = -0.032
CASTER_X_M = -0.081
CASTER_RADIUS_M = 0.01
CHASSIS_HALF_SIZE_M = (0.069, 0.069, 0.05)
CHASSIS_COM_Z_M = 0.07
# Contact of tyres and floor: MuJoCo's time constant of the contact spring (its default is
# 0.02 s, a soft floor the wheels sink 0.33 mm into and creep on). 4 ms is a hard floor and a
# firm tyre; MuJoCo asks for at least two physics steps per time constant.
CONTACT_TIME_CONSTANT_S = 0.004
TORSION_FRICTION, ROLLING_FRICTION = 0.005, 0.0001
# The motor's rotor inertia as the wheel feels it through the gearbox [kg m^2] (MuJoCo's joint
# armature): a Dynamixel XL430's 258.5:1 gearing makes it about 1e-3, twice what the base's
# own mass reflects onto a wheel. Without it a bare 30 g wheel answered the velocity loop in
# 0.1 ms, far inside a physics step, and braking pitched the base onto its nose.
WHEEL_ARMATURE = 0.001


@dataclass(frozen=True)
class BaseSpec:
    """What a user tunes of the base: dimensions, mass, motors, tyres, the physics step."""

    wheel_radius: float = 0.033  # m
    wheel_separation: float = 0.160  # m, between the tyres' contact points
    mass: float = 1.0  # kg, all of it
    max_wheel_speed: float = 6.9  # rad/s: 0.22 m/s forwards, 2.84 rad/s turning in place
    max_wheel_torque: float = 1.4  # N m: a Dynamixel XL430-W250's stall torque
    motor_gain: float = 0.5  # N m per rad/s of speed error: the motors' velocity loop
    tire_friction: float = 1.0  # sliding friction coefficient, rubber on a hard floor
    timestep: float = 0.002  # s, one physics step

    def problems(self) -> list[str]:
        """What is wrong with these values, each a sentence (none: a model can be built)."""
        found = [f'{item.name} must be a finite number, got {getattr(self, item.name)!r}'
                 for item in fields(self) if not math.isfinite(getattr(self, item.name))]
        if found:
            return found
        found = [f'{item.name} must be above 0, got {getattr(self, item.name):g}'
                 for item in fields(self) if getattr(self, item.name) <= 0.0]
        if found:
            return found
        if self.wheel_radius <= CASTER_RADIUS_M:
            found.append(f'wheel_radius must be above the caster radius {CASTER_RADIUS_M:g} m, '
                         f'got {self.wheel_radius:g}')
        if self.wheel_separation <= 2 * 0.009:
            found.append(f'wheel_separation must leave room for two 18 mm tyres, got '
                         f'{self.wheel_separation:g}')
        if self.timestep * 2 > CONTACT_TIME_CONSTANT_S:  # read at call time
            found.append(f'timestep must be at most {CONTACT_TIME_CONSTANT_S / 2:g} s (two '
                         f'steps per contact time constant), got {self.timestep:g}')
        return found

    @property
    def top_speed(self) -> float:
        """The fastest a wheel's rim moves [m/s]."""
        return self.max_wheel_speed * self.wheel_radius


def mjcf(spec: BaseSpec) -> str:
    """The MuJoCo model of `spec`: a floor, the chassis on a free joint, two velocity-driven
    wheels and a frictionless caster. The body frame is base_footprint: on the floor, midway
    between the wheels, x forwards."""
    r, half = spec.wheel_radius, spec.wheel_separation / 2
    wheel_mass = WHEEL_MASS_SHARE * spec.mass
    caster_mass = CASTER_MASS_SHARE * spec.mass
    chassis_mass = spec.mass - 2 * wheel_mass - caster_mass
    hx, hy, hz = CHASSIS_HALF_SIZE_M
    friction = f'{spec.tire_friction:.17g} {TORSION_FRICTION} {ROLLING_FRICTION}'
    # A tyre touches the floor at one point, as a sphere of the wheel's radius does: a MuJoCo
    # cylinder touches at its two rims, 18 mm apart, whose friction resisted turning in place
    # (8% short of what the wheels turned, measured).
    wheels = ''.join(
        f'<body name="{side}_wheel" pos="0 {sign * half:.17g} {r:.17g}">'
        f'<joint name="{side}_wheel_joint" type="hinge" axis="0 1 0" '
        f'armature="{WHEEL_ARMATURE}"/>'
        f'<geom name="{side}_tyre" type="sphere" size="{r:.17g}" mass="{wheel_mass:.17g}" '
        f'friction="{friction}"/></body>'
        for side, sign in (('left', 1), ('right', -1)))
    motors = ''.join(
        f'<velocity name="{side}_motor" joint="{side}_wheel_joint" kv="{spec.motor_gain:.17g}" '
        f'forcelimited="true" forcerange="{-spec.max_wheel_torque:.17g} '
        f'{spec.max_wheel_torque:.17g}"/>' for side in ('left', 'right'))
    return (
        f'<mujoco model="turtle_traj_base">'
        f'<option timestep="{spec.timestep:.17g}" integrator="implicitfast"/>'
        f'<worldbody>'
        f'<geom name="floor" type="plane" size="0 0 1" friction="{friction}" '
        f'solref="{CONTACT_TIME_CONSTANT_S} 1"/>'
        f'<body name="base_footprint">'
        f'<freejoint name="base"/>'
        f'<geom name="chassis" type="box" size="{hx} {hy} {hz}" '
        f'pos="{CHASSIS_COM_X_M} 0 {CHASSIS_COM_Z_M}" mass="{chassis_mass:.17g}" contype="0" '
        f'conaffinity="0"/>'
        f'<geom name="caster" type="sphere" size="{CASTER_RADIUS_M}" '
        f'pos="{CASTER_X_M} 0 {CASTER_RADIUS_M}" mass="{caster_mass:.17g}" condim="1" '
        f'priority="1" friction="0 0 0"/>'
        f'{wheels}</body></worldbody>'
        f'<actuator>{motors}</actuator></mujoco>')
