"""Shared fixtures: the repository root (scenarios, experiments) and the CLI binary."""
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def vitro_bin():
    """The `vitro` binary to compare with: $VITRO_BIN, else target/debug/vitro."""
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    path = Path(os.environ.get("VITRO_BIN", target / "debug" / "vitro"))
    if not path.is_file():
        pytest.fail(f"no vitro binary at {path}: build it (cargo build -p vitro-cli) or set VITRO_BIN")
    return path
