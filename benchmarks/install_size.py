"""What an install weighs: the site-packages of a fresh virtual environment after
``pip install`` of the built wheel, alone and with each extra, and what ``make run`` and
``make test`` leave in ``.venv`` (the README quotes these figures).

    .venv/bin/python benchmarks/install_size.py            # builds the wheel first (minutes)
    .venv/bin/python benchmarks/install_size.py --wheel target/wheels/multibots-*.whl

Needs the network (or a package cache) for the dependencies. Prints one line per install.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def folder_size(path: Path) -> int:
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file() and not p.is_symlink())


def site_packages(env: Path) -> Path:
    return next((env / "lib").glob("python*/site-packages"))


def build_wheel(out: Path) -> Path:
    # The maturin beside this interpreter (.venv/bin), else the one on PATH.
    beside = Path(sys.executable).parent / "maturin"
    maturin = str(beside) if beside.exists() else "maturin"
    subprocess.run([maturin, "build", "--release", "--out", str(out), "-q"], cwd=ROOT, check=True)
    return next(out.glob("multibots-*.whl"))


def installed(wheel: Path, extras: str, pip_args: list[str]) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        env = Path(tmp) / "env"
        venv.EnvBuilder(with_pip=True).create(env)
        target = f"{wheel}[{extras}]" if extras else str(wheel)
        subprocess.run([str(env / "bin" / "python"), "-m", "pip", "install", "-q", *pip_args, target], check=True)
        return folder_size(site_packages(env))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--wheel", type=Path, help="an already built wheel (default: build one with maturin)")
    ap.add_argument("--pip", default="", help="extra pip arguments, such as '--no-cache-dir'")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        wheel = args.wheel or build_wheel(Path(tmp))
        pip_args = args.pip.split()
        print(f"python {sys.version.split()[0]}, wheel {wheel.name}")
        for label, extras in [("pip install .", ""), ("with study (polars)", "study"),
                              ("with render", "render"), ("make run: core + maturin", "MATURIN"),
                              ("make test: + test, lint extras", "test,lint")]:
            if extras == "MATURIN":
                size = installed(wheel, "", [*pip_args, "maturin>=1.7,<2"])
            else:
                size = installed(wheel, extras, pip_args)
            print(f"{label:<32} {size / 1e6:8.0f} MB of site-packages")


if __name__ == "__main__":
    main()
