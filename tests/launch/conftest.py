"""Fixtures of the launch tests: a workspace in tmp_path."""

from __future__ import annotations

from pathlib import Path

import pytest

from .workspace import Workspace


@pytest.fixture
def ws(tmp_path: Path) -> Workspace:
    """An empty workspace; packages and launch files are written by each test."""
    return Workspace(tmp_path)
