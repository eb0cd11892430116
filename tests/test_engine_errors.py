"""Errors cross the binding as exceptions of one tree; a panic never kills the interpreter."""

import pytest

import multibots
from multibots import _core


def test_exception_tree():
    for cls in (multibots.ScenarioError, multibots.LayoutError, multibots.AllocatorError, multibots.EngineError, multibots.ReplayError):
        assert issubclass(cls, multibots.MultibotsError)


def test_a_panic_becomes_an_engine_error_and_python_goes_on():
    with pytest.raises(multibots.EngineError, match="deliberate panic"):
        _core._panic_for_tests()
    # The interpreter and the engine still work.
    assert multibots.simulate(multibots.Scenario.paper(robots=1, goods=[42])).T == 726


def test_stepping_after_the_end_is_harmless():
    sim = multibots.Simulation(multibots.Scenario.paper(robots=1, goods=[42]))
    sim.run()
    assert sim.step(10) == 0 and sim.t == 726
    with pytest.raises(ValueError):
        sim.step(-1)
    with pytest.raises(IndexError):
        sim.route(5)
