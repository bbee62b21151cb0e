"""Rolling and spinning friction (Bullet's model, Habitat's coefficients): a rolling ball
decelerates at ``mu_roll g / (r (1 + I / (m r^2)))``, a spinning ball stops spinning, and the
scalar and vectorized solver paths agree."""

from __future__ import annotations

import numpy as np
import pytest

from engine.physics import MotionType
from engine.simulator import Configuration, Simulator, SimulatorConfiguration

RADIUS = 0.1  # the icosphere primitive template at scale 0.1
GRAVITY = 9.8


def ball_on_slab(rolling: float = 0.0, spinning: float = 0.0, vectorized: bool = True):
    """A 0.1 m ball resting on a static 4 m slab (top at y = 0.1), no damping anywhere."""
    sim = Simulator(Configuration(SimulatorConfiguration(scene_id="NONE")))
    sim.get_physics_world().settings.use_vectorized = vectorized
    manager = sim.get_object_template_manager()
    slab = manager.get_template_by_handle("cubeSolid")
    slab.scale = [20.0, 0.1, 20.0]
    manager.register_template(slab, "slab")
    rom = sim.get_rigid_object_manager()
    floor = rom.add_object_by_template_handle("slab")
    floor.motion_type = MotionType.STATIC
    floor.friction_coefficient = 1.0
    ball = rom.add_object_by_template_handle("icosphereSolid_subdivs_1")
    ball.translation = [0.0, 0.1 + RADIUS, 0.0]
    ball.linear_damping = ball.angular_damping = 0.0
    ball.friction_coefficient = 1.0
    ball.rolling_friction_coefficient = rolling
    ball.spinning_friction_coefficient = spinning
    return sim, ball


def roll(sim, ball, speed: float = 2.0) -> None:
    """Start rolling along +x without slipping: w = v / r about -z."""
    ball.linear_velocity = [speed, 0.0, 0.0]
    ball.angular_velocity = [0.0, 0.0, -speed / RADIUS]
    sim.step_physics(0.1)


def expected_rolling_deceleration(ball, mu_roll_pair: float) -> float:
    inertia = float(np.asarray(ball.intertia_diagonal)[2])
    return mu_roll_pair * GRAVITY / (RADIUS * (1.0 + inertia / (ball.mass * RADIUS**2)))


def test_rolling_ball_decelerates_as_bullet_models_rolling_friction():
    mu = 0.01  # pair value r_ball f_floor + r_floor f_ball = 0.01 * 1 + 0 * 1
    sim, ball = ball_on_slab(rolling=mu)
    with sim:
        roll(sim, ball)
        v0, t0 = ball.linear_velocity.x, sim.get_world_time()
        sim.step_physics(1.0)
        deceleration = (v0 - ball.linear_velocity.x) / (sim.get_world_time() - t0)
        # a = mu g / (r (1 + I / (m r^2))) = 5/7 mu g / r for a solid sphere: about 0.7 m/s^2
        assert deceleration == pytest.approx(expected_rolling_deceleration(ball, mu), rel=0.1)
        # still rolling without slipping
        assert ball.angular_velocity.z == pytest.approx(-ball.linear_velocity.x / RADIUS, rel=0.02)


def test_without_rolling_friction_the_ball_keeps_rolling():
    sim, ball = ball_on_slab(rolling=0.0)
    with sim:
        roll(sim, ball)
        v0 = ball.linear_velocity.x
        sim.step_physics(1.0)
        assert ball.linear_velocity.x == pytest.approx(v0, rel=0.01)


def test_spinning_friction_stops_a_spinning_ball():
    mu = 0.01
    for spinning, still_spinning in ((mu, False), (0.0, True)):
        sim, ball = ball_on_slab(spinning=spinning)
        with sim:
            sim.step_physics(0.1)  # settle on the slab
            ball.angular_velocity = [0.0, 10.0, 0.0]
            sim.step_physics(0.2)
            inertia = float(np.asarray(ball.intertia_diagonal)[1])
            if spinning:
                # alpha = mu N / I = mu m g / I: 10 rad/s - 0.2 s alpha
                alpha = mu * ball.mass * GRAVITY / inertia
                assert ball.angular_velocity.y == pytest.approx(10.0 - 0.2 * alpha, rel=0.1)
            sim.step_physics(1.0)
            spin = ball.angular_velocity.y
            assert (spin > 9.9) if still_spinning else (abs(spin) < 0.05)


def test_both_solver_paths_agree_on_rolling_and_spinning():
    finals = []
    for vectorized in (True, False):
        sim, ball = ball_on_slab(rolling=0.02, spinning=0.01, vectorized=vectorized)
        with sim:
            roll(sim, ball)
            ball.angular_velocity = ball.angular_velocity + [0.0, 5.0, 0.0]
            sim.step_physics(0.5)
            finals.append(
                np.concatenate([ball.translation, ball.linear_velocity, ball.angular_velocity])
            )
    np.testing.assert_allclose(finals[0], finals[1], atol=1e-9)


def _count_contact_loads(monkeypatch) -> list:
    """Record every ContactLoads (rolling friction's input) either solve path builds."""
    from engine.physics.pipeline import solve_stage
    from engine.physics.reference import reference_solver
    from engine.physics.solver.rolling_friction import ContactLoads

    built = []

    def counting(*fields):
        built.append(len(fields[0]))  # manifolds in the loads
        return ContactLoads(*fields)

    monkeypatch.setattr(solve_stage, "ContactLoads", counting)
    monkeypatch.setattr(reference_solver, "ContactLoads", counting)
    return built


def rolled_state(vectorized: bool, rolling: float = 0.0) -> str:
    """State hash of the ball after rolling 0.35 s on the slab."""
    sim, ball = ball_on_slab(rolling=rolling, vectorized=vectorized)
    with sim:
        roll(sim, ball)
        sim.step_physics(0.25)
        return sim.get_physics_world().state_hash()


@pytest.mark.parametrize("vectorized", [True, False])
def test_all_zero_coefficients_skip_rolling_friction_and_change_nothing(monkeypatch, vectorized):
    from engine.physics.pipeline import solve_stage

    built = _count_contact_loads(monkeypatch)
    skipped = rolled_state(vectorized)
    assert built == []  # no body has a rolling or spinning coefficient: no loads built
    # forcing the rolling-friction pass (every pair coefficient 0) gives the same bits
    monkeypatch.setattr(solve_stage, "needs_rolling_friction", lambda *_: True)
    assert rolled_state(vectorized) == skipped
    assert len(built) > 0 and all(count > 0 for count in built)
    # a ball with rolling friction brings the pass back, and it changes the result
    monkeypatch.undo()
    built = _count_contact_loads(monkeypatch)
    assert rolled_state(vectorized, rolling=0.01) != skipped
    assert len(built) > 0
