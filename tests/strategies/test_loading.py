"""Strategies named by text: ``package.module:Class``, ``module:Class`` in the current folder and
``path/to/file.py:Class``, loaded by one function, with one-line errors."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from multibots import Scenario, ScenarioError, simulate
from multibots.strategies import load_strategy, strategy_source

MINE = """
import multibots


class InTurn(multibots.Allocator):
    def allocate(self, view):
        return list(zip(view.idle.tolist(), view.goods.tolist()))


NOT_CALLABLE = 3
"""

S = Scenario.paper(robots=2, goods=[11, 8, 39])


@pytest.fixture()
def folder(tmp_path, monkeypatch):
    """A folder holding a strategy file (mine_<id>.py), made the current folder."""
    name = f"mine_{abs(hash(str(tmp_path))) % 10**8}"
    (tmp_path / f"{name}.py").write_text(MINE, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    yield tmp_path, name
    sys.modules.pop(name, None)


def test_a_file_path_relative_or_absolute(folder):
    path, name = folder
    want = simulate(S, allocator="in-turn")
    for spec in (f"{name}.py:InTurn", f"./{name}.py:InTurn", f"{path / name}.py:InTurn"):
        assert simulate(S, allocator=spec) == want, spec
        assert simulate(S.replace(allocator=spec)) == want, spec
    assert load_strategy(f"{name}.py:InTurn").__name__ == "InTurn"
    assert strategy_source(f"{name}.py:InTurn") == MINE.encode()


def test_a_module_in_the_current_folder_without_touching_sys_path(folder):
    path, name = folder
    before = list(sys.path)
    assert simulate(S, allocator=f"{name}:InTurn") == simulate(S, allocator="in-turn")
    assert sys.path == before and str(path) not in sys.path


def test_an_edited_file_is_loaded_again(folder):
    path, name = folder
    first = load_strategy(f"{name}.py:InTurn")
    assert load_strategy(f"{name}.py:InTurn") is first  # not executed again for every run
    (path / f"{name}.py").write_text(MINE + "\n\nclass Other(InTurn):\n    pass\n", encoding="utf-8")
    assert load_strategy(f"{name}.py:Other").__name__ == "Other"


@pytest.mark.parametrize(
    ("spec", "why"),
    [
        ("nowhere/mine.py:InTurn", "no such file nowhere/mine.py"),
        ("NAME.py:Nope", "module NAME.py has no attribute Nope"),
        ("NAME.py:NOT_CALLABLE", "NOT_CALLABLE is not a class or function"),
        ("broken.py:InTurn", "cannot import broken.py: SyntaxError: "),
        ("raises.py:InTurn", "cannot import raises.py: RuntimeError: at import"),
        ("no_such_module_here:InTurn", "cannot import no_such_module_here: ModuleNotFoundError"),
        ("NAME.py:", 'expected "package.module:Class" or "path/to/file.py:Class"'),
        (".", 'expected "package.module:Class"'),
    ],
)
def test_bad_names_are_one_line_scenario_errors(folder, spec, why):
    path, name = folder
    (path / "broken.py").write_text("def f(:\n    pass\n", encoding="utf-8")
    (path / "raises.py").write_text("raise RuntimeError('at import')\n", encoding="utf-8")
    spec, why = spec.replace("NAME", name), why.replace("NAME", name)
    with pytest.raises(ScenarioError) as e:
        load_strategy(spec) if ":" in spec else load_strategy(spec + ":")
    assert str(e.value).startswith(f'allocator = "{spec if ":" in spec else spec + ":"}": ')
    assert why in str(e.value) and "\n" not in str(e.value), str(e.value)


def _script(cli):
    """The installed ``multibots`` script: unlike ``python -m``, it does not put the current
    folder on sys.path, so this is what a user's shell runs."""
    script = Path(sys.executable).parent / "multibots"
    assert script.is_file()
    return [str(script)]


def test_the_command_line_takes_both_forms(cli, tmp_path, monkeypatch):
    (tmp_path / "mystrat.py").write_text(MINE, encoding="utf-8")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "other.py").write_text(MINE, encoding="utf-8")
    monkeypatch.setattr(cli, "argv", _script(cli))
    want = cli("run", "--robots", "2", "--goods", "11,8,39", "--json", cwd=tmp_path).stdout
    for spec in ("mystrat:InTurn", "mystrat.py:InTurn", "sub/other.py:InTurn"):
        p = cli("run", "--robots", "2", "--goods", "11,8,39", "--allocator", spec, "--json", cwd=tmp_path)
        assert p.returncode == 0, (spec, p.stderr)
        assert p.stdout == want, spec
    (tmp_path / "bad.py").write_text("class X(:\n", encoding="utf-8")
    for spec, why in [("nope.py:InTurn", "no such file nope.py"), ("mystrat:Nope", "has no attribute Nope"),
                      ("bad.py:X", "SyntaxError")]:
        p = cli("run", "--goods", "1", "--allocator", spec, cwd=tmp_path)
        cli.assert_one_line_error(p, f'allocator = "{spec}"', why)
