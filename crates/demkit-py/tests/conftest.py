"""Shared fixtures: the command-line binary and small generated meshes."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

import demkit

REPO = Path(__file__).resolve().parents[3]


def cli_path() -> Path | None:
    """The `demkit` binary: $DEMKIT_CLI, else the release build of this checkout."""
    if os.environ.get("DEMKIT_CLI"):
        return Path(os.environ["DEMKIT_CLI"])
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    candidate = target / "release" / "demkit"
    if candidate.exists():
        return candidate
    found = shutil.which("demkit")
    return Path(found) if found else None


@pytest.fixture(scope="session")
def cli() -> Path:
    path = cli_path()
    if path is None or not path.exists():
        pytest.fail("the demkit binary is needed: build it with `cargo build --release` or set DEMKIT_CLI")
    return path


@pytest.fixture(scope="session")
def disk():
    return demkit.generate("polygon", sides=6, rings=12)


@pytest.fixture(scope="session")
def sphere():
    return demkit.generate("icosphere", subdivisions=2)


@pytest.fixture(scope="session")
def holes():
    return demkit.generate("disk_holes", holes=[(0.4, 0.0, 0.2), (-0.4, 0.1, 0.15)], resolution=40)


@pytest.fixture(scope="session")
def torus():
    return demkit.generate("torus", R=2.0, r=1.0, major=32, minor=16)
