"""The pure-Python reference model (tests/oracle/reference_model.py) and its agreement with
the engine.

The reference is an independent implementation of docs/model.md; the engine must give
identical T, S, C, outcome, steps and delivered for every scenario.
"""

import math
import random
import tempfile

import pytest

from oracle import reference_model as ref


def _engine():
    """The engine's Python package. A broken build must fail these tests, never skip them:
    they are the independent check that the engine follows the spec."""
    import multibots

    return multibots


# ---------------------------------------------------------------------------------------
# The reference alone
# ---------------------------------------------------------------------------------------


def _route_len(pos, loc, target):
    points, _, _ = ref.make_route(pos, loc, target)
    return ref.route_length(points)


def test_worked_example_paths_and_lengths():
    ch0 = ref.charger_id(0)
    point, edge = ref.cell_service_point(42)
    assert point == (325.0, 375.0)
    assert [ref.NODE_NAMES[n] for n in edge] == ["O", "I"]
    path = ref.node_path(ref.node_id("A"), edge[0])
    assert "".join(ref.NODE_NAMES[n] for n in path) == "ABCDJPO"

    d1 = _route_len(ref.NODE_XY[ch0], ("node", ch0), ("point", point, edge))
    d2 = _route_len(point, ("edge", edge), ("node", ref.node_id("M")))
    d3 = _route_len(ref.NODE_XY[ref.node_id("M")], ("node", ref.node_id("M")), ("node", ch0))
    assert (d1, d2, d3) == (1290.0, 950.0, 540.0)


def test_worked_example_T_726():
    res = ref.run([42], robots=1)
    assert res["T"] == 726
    assert res["outcome"] == "complete"
    assert res["steps"] == 726
    assert res["delivered"] == 1
    assert res["S"] == 0 and res["C"] == 0
    assert res["distance"] == [1290.0 + 950.0 + 540.0]
    assert res["stranded"] == []


def _formula(d1, d2, d3, loading=10, unloading=20):
    return math.ceil(d1 / 4) + loading + math.ceil(d2 / 4) + unloading + math.ceil(d3 / 4)


# (cell, start, unload, D1, D2, D3), route lengths worked out by hand from the layout.
HAND_ROUTES = [
    (42, "A", "M", 1290, 950, 540),   # the paper's worked example
    (0, "A", "M", 1290, 850, 540),    # CH0 A B H N M G, up to (25, 75); A B H N M; M G A CH0
    (79, "A", "M", 1240, 800, 540),   # CH0 A B C D E F L, down to (775, 475); R Q P O N M
    (42, "D", "O", 840, 650, 690),    # CH3 D J P O, up; I J P O; O I C D CH3
    (42, "D", "M", 840, 950, 990),    # ...; M G H I C D CH3
]


@pytest.mark.parametrize("cell,start,unload,d1,d2,d3", HAND_ROUTES)
def test_single_robot_formula(cell, start, unload, d1, d2, d3):
    res = ref.run([cell], robots=1, starts=[start], unload=unload)
    assert res["T"] == _formula(d1, d2, d3)
    assert res["distance"] == [float(d1 + d2 + d3)]


@pytest.mark.parametrize("cell", [0, 7, 13, 26, 42, 55, 64, 79])
def test_single_robot_formula_from_route_lengths(cell):
    """T = ceil(D1/4) + 10 + ceil(D2/4) + 20 + ceil(D3/4), with the reference's routes."""
    ch0 = ref.charger_id(0)
    m = ref.node_id("M")
    point, edge = ref.cell_service_point(cell)
    d1 = _route_len(ref.NODE_XY[ch0], ("node", ch0), ("point", point, edge))
    d2 = _route_len(point, ("edge", edge), ("node", m))
    d3 = _route_len(ref.NODE_XY[m], ("node", m), ("node", ch0))
    assert ref.run([cell], robots=1)["T"] == _formula(d1, d2, d3)
    assert ref.run([cell], robots=1, loading_steps=3, unloading_steps=7)["T"] == _formula(
        d1, d2, d3, 3, 7)


def test_step_limit_makes_run_incomplete():
    res = ref.run([42], robots=1, step_limit=725)
    assert res["T"] is None
    assert res["outcome"] == "incomplete"
    assert res["steps"] == 725
    assert res["delivered"] == 1


def test_robot_strands_when_energy_runs_out():
    # 1.0 energy lasts 200 steps; the threshold rule sends it home from the middle of its
    # first trip, and it runs dry on the way: the run ends the step the fleet is stranded.
    res = ref.run([42], robots=1, energy_full=1.0, threshold=0.5, step_limit=3000)
    assert res["outcome"] == "stranded" and res["T"] is None
    assert res["stranded"] == [0]
    assert res["delivered"] == 0
    assert res["steps"] == 200


def test_marked_robot_charges_after_unloading():
    # Below threshold once inside its service point's edge: it loads, unloads, then goes
    # to charge (C = 1); the run ends when it reaches its charger (whatever its state).
    res = ref.run([42], robots=1, energy_full=5.0, threshold=3.5)
    assert (res["T"], res["C"], res["charges"]) == (726, 1, [1])


def test_put_back_goods_go_to_the_front_of_the_queue():
    # Robot 0 fetches 42 (via A B C D J P O), robot 1 fetches 0 (via B H N M G). Both fall
    # below threshold in step 101, before reaching their service edges, and put their
    # goods back, robot 0 first: the queue becomes [0, 42, 79]. Robot 1, charged first,
    # takes 0 again and so turns south at B (towards H), not east (towards C and 42).
    trace = []
    ref.run([42, 0, 79], robots=2, energy_full=4.0, threshold=3.5, step_limit=400,
            trace=trace)

    def robot(t, i):
        return trace[t - 1][4][i]

    assert [robot(100, i)[2] for i in (0, 1)] == ["TO_PICKUP", "TO_PICKUP"]
    assert [robot(101, i)[2] for i in (0, 1)] == ["TO_CHARGER", "TO_CHARGER"]
    assert robot(380, 1)[2] == "IDLE" and robot(381, 1)[2] == "TO_PICKUP"
    assert robot(390, 1)[:2] == (175.0, 25.0)       # node B
    assert robot(391, 1)[:2] == (175.0, 29.0)       # heading south, to cell 0


def test_paper_table_completes():
    for n, group, res in ref.paper_table():
        assert res["outcome"] == "complete", (n, group)
        assert res["delivered"] == 10
        assert sum(res["delivered_by_robot"]) == 10
        assert sum(res["charges"]) == res["C"]


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(goods=[]),
        dict(goods=[1, 1]),
        dict(goods=[80]),
        dict(goods=[-1]),
        dict(goods=[1], robots=7),
        dict(goods=[1], robots=0),
        dict(goods=[1], robots=2, starts=["A", "A"]),
        dict(goods=[1], robots=1, starts=["M"]),
        dict(goods=[1], unload="A"),
    ],
)
def test_rejects_bad_scenarios(kwargs):
    with pytest.raises(ValueError):
        ref.run(**kwargs)


# ---------------------------------------------------------------------------------------
# Agreement with the engine
# ---------------------------------------------------------------------------------------


def _norm_outcome(outcome):
    text = str(getattr(outcome, "value", outcome)).lower()
    if "incomplete" in text:
        return "incomplete"
    if "complete" in text:
        return "complete"
    return text


def _first_difference(mb, scenario, trace):
    """Where the engine's replay and the reference's trace first differ (for messages)."""
    try:
        with tempfile.TemporaryDirectory() as tmp:
            path = tmp + "/run.mbr"
            mb.simulate(scenario, record=path)
            replay = mb.Replay(path)
            try:
                for t, s, c, delivered, robots in trace:
                    if t >= replay.frames:
                        return "the engine's replay ends before step %d" % t
                    frame = replay.frame(t)
                    if (frame["S"], frame["C"], frame["delivered"]) != (s, c, delivered):
                        return "step %d: engine S, C, delivered = %r, reference %r" % (
                            t, (frame["S"], frame["C"], frame["delivered"]), (s, c, delivered))
                    for i, (x, y, state, marked, _energy) in enumerate(robots):
                        ex, ey = float(frame["x"][i]), float(frame["y"][i])
                        estate = STATE_NAMES.get(int(frame["state"][i]), frame["state"][i])
                        if abs(ex - x) > 1e-3 or abs(ey - y) > 1e-3 or estate != state:
                            return ("step %d, robot %d: engine (%.3f, %.3f, %s), reference "
                                    "(%.3f, %.3f, %s)" % (t, i, ex, ey, estate, x, y, state))
                        if bool(frame["marked"][i]) != marked:
                            return "step %d, robot %d: 'marked to charge' differs" % (t, i)
                return "no per-step difference found"
            finally:
                replay.close()
    except Exception as exc:  # the diagnosis is best effort only
        return "could not compare replays: %r" % (exc,)


STATE_NAMES = {0: "IDLE", 1: "TO_PICKUP", 2: "LOADING", 3: "TO_DROP", 4: "UNLOADING",
               5: "TO_CHARGER", 6: "CHARGING", 7: "TO_HOME", 8: "PARKED", 9: "STRANDED",
               10: "WAIT_CHARGER"}


def _compare(robots, goods, margin, starts=None, unload="M", step_limit=100000):
    mb = _engine()
    scenario = mb.Scenario.paper(robots=robots, goods=list(goods), starts=starts,
                                 unload=unload, margin=margin, step_limit=step_limit)
    got = mb.simulate(scenario)
    trace = []
    want = ref.run(list(goods), robots=robots, starts=starts, unload=unload,
                   margin=margin, step_limit=step_limit, trace=trace)
    engine = {
        "T": got.T, "S": got.S, "C": got.C, "outcome": _norm_outcome(got.outcome),
        "steps": got.steps, "delivered": got.delivered,
    }
    reference = {key: want[key] for key in engine}
    if engine != reference:
        pytest.fail(
            "engine and reference disagree for robots=%d goods=%r margin=%r starts=%r "
            "unload=%r step_limit=%d\n  engine:    %r\n  reference: %r\n  first difference: %s"
            % (robots, list(goods), margin, starts, unload, step_limit, engine, reference,
               _first_difference(mb, scenario, trace)))


PAPER_CASES = [
    (n, group, margin)
    for margin in (0.0, 8.0)
    for n in range(1, 7)
    for group in sorted(ref.PAPER_GROUPS)
]


@pytest.mark.parametrize("n,group,margin", PAPER_CASES)
def test_engine_agrees_on_paper_runs(n, group, margin):
    _compare(n, ref.PAPER_GROUPS[group], margin)


def _random_scenario(seed):
    rng = random.Random(seed)
    robots = rng.randint(1, 6)
    count = rng.randint(1, 10)
    goods = rng.sample(range(80), count)
    margin = rng.choice([0.0, 8.0])
    return robots, goods, margin


@pytest.mark.parametrize("seed", range(100))
def test_engine_agrees_on_random_scenarios(seed):
    robots, goods, margin = _random_scenario(seed)
    _compare(robots, goods, margin)


def _random_placement(seed):
    """Random start nodes and unloading zone as well (seeds offset from the ones above)."""
    rng = random.Random(10000 + seed)
    robots = rng.randint(1, 6)
    goods = rng.sample(range(80), rng.randint(1, 10))
    starts = rng.sample(list(ref.DEPARTURE_ZONES), robots)
    unload = rng.choice(list(ref.UNLOADING_ZONES))
    margin = rng.choice([0.0, 8.0])
    return robots, goods, margin, starts, unload


@pytest.mark.parametrize("seed", range(12))
def test_engine_agrees_with_other_starts_and_unloading_zones(seed):
    robots, goods, margin, starts, unload = _random_placement(seed)
    _compare(robots, goods, margin, starts=starts, unload=unload)


def _random_parameters(seed):
    """Other robot, dwell and collision parameters: charging, put-backs, stranding."""
    rng = random.Random(20000 + seed)
    robots = rng.randint(1, 6)
    goods = rng.sample(range(80), rng.randint(1, 10))
    margin = rng.choice([0.0, 8.0, 20.0])
    energy_full = rng.choice([10.0, 5.0])
    params = dict(
        radius=rng.choice([12.5, 5.0, 20.0]),
        speed=rng.choice([4.0, 2.0, 5.0, 10.0]),
        energy_full=energy_full,
        threshold=rng.choice([2.0, 3.5, 4.5]) if energy_full > 5 else rng.choice([1.5, 2.5, 3.5]),
        consumption=rng.choice([0.005, 0.005, 0.01]),
        charge_rate=rng.choice([0.05, 0.1, 0.3]),
        loading_steps=rng.choice([10, 1, 5]),
        unloading_steps=rng.choice([20, 1, 7]),
        angle_deg=rng.choice([30.0, 45.0, 10.0, 90.0]),
    )
    return robots, goods, margin, params


@pytest.mark.parametrize("seed", range(20))
def test_engine_agrees_with_other_parameters(seed):
    mb = _engine()
    robots, goods, margin, p = _random_parameters(seed)
    step_limit = 4000
    trace = []
    want = ref.run(goods, robots=robots, margin=margin, step_limit=step_limit, trace=trace, **p)
    try:
        scenario = mb.Scenario.paper(
            robots=robots, goods=goods, margin=margin, step_limit=step_limit,
            robot=dict(radius=p["radius"], speed=p["speed"], energy_full=p["energy_full"],
                       threshold=p["threshold"], consumption=p["consumption"],
                       charge_rate=p["charge_rate"]),
            dwell=dict(loading=p["loading_steps"], unloading=p["unloading_steps"]),
            collision=dict(margin=margin, angle=p["angle_deg"]))
    except mb.ScenarioError as e:
        # The engine refuses work no battery can carry (not even the easiest task): the
        # reference, which has no such check, must then deliver nothing.
        assert "turn back to charge" in str(e) or "round trip" in str(e), e
        assert want["delivered"] == 0, (str(e), want)
        return
    got = mb.simulate(scenario)
    engine = (got.T, got.S, got.C, _norm_outcome(got.outcome), got.steps, got.delivered)
    reference = (want["T"], want["S"], want["C"], want["outcome"], want["steps"],
                 want["delivered"])
    if engine != reference:
        pytest.fail("engine %r != reference %r for robots=%d goods=%r margin=%r %r\n"
                    "  first difference: %s" % (engine, reference, robots, goods, margin, p,
                                                _first_difference(mb, scenario, trace)))


@pytest.mark.parametrize("step_limit", [1, 300, 725, 726, 1500])
def test_engine_agrees_at_the_step_limit(step_limit):
    _compare(3, ref.PAPER_GROUPS[1], 0.0, step_limit=step_limit)
    _compare(1, [42], 0.0, step_limit=step_limit)
