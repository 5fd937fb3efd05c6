"""Shared fixtures: where the repository and the `carfollow` binary are."""

import os
import pathlib
import shutil

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]
SCENARIOS = REPO / "scenarios"


@pytest.fixture(scope="session")
def carfollow_bin() -> pathlib.Path:
    """The `carfollow` command line, built by `cargo build --release` (or CARFOLLOW_BIN)."""
    given = os.environ.get("CARFOLLOW_BIN")
    candidates = [pathlib.Path(given)] if given else []
    # Cargo's build folder: CARGO_TARGET_DIR where set (as `.ci/test` honours it), else the
    # workspace's own.
    target = os.environ.get("CARGO_TARGET_DIR")
    if target:
        candidates.append(pathlib.Path(target) / "release" / "carfollow")
    candidates.append(REPO / "target" / "release" / "carfollow")
    found = shutil.which("carfollow")
    if found:
        candidates.append(pathlib.Path(found))
    for c in candidates:
        if c.is_file():
            return c
    pytest.fail("no carfollow binary: run `cargo build --release` first, or set CARFOLLOW_BIN")
