"""Shared fixtures: the repository, the CLI binary the package is compared with, and its
output. The CLI is `$CWSYNTH_CLI`, else `target/release/cwsynth` (built from the same
workspace and lock file as the extension; `cargo build --release --bin cwsynth` reuses the
extension's compiled library)."""

import json
import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PROBLEMS = sorted((REPO / "problems").glob("*.toml"))


def cli_path() -> Path:
    env = os.environ.get("CWSYNTH_CLI")
    p = Path(env) if env else REPO / "target" / "release" / "cwsynth"
    if not p.exists():
        subprocess.run(
            ["cargo", "build", "--release", "--bin", "cwsynth"], cwd=REPO, check=True
        )
    return p


@pytest.fixture(scope="session")
def cli():
    """Runs the CLI in the repository's directory: `cli("solve", "--json", f)`."""
    exe = cli_path()

    def run(*args, check=False, cwd=REPO):
        return subprocess.run(
            [str(exe), *map(str, args)], cwd=cwd, capture_output=True, text=True, check=check
        )

    return run


@pytest.fixture
def in_repo(monkeypatch):
    """Work in the repository's directory, so relative problem paths (and the results'
    `source`) are the same for the CLI and the package."""
    monkeypatch.chdir(REPO)
    return REPO


def without(d, *keys):
    """`d` without the given top-level keys."""
    return {k: v for k, v in d.items() if k not in keys}


def cli_json(cli, rel):
    """`cwsynth solve --json REL` as a dict."""
    out = cli("solve", "--json", rel)
    assert out.stdout.strip(), out.stderr
    lines = out.stdout.splitlines()
    assert len(lines) == 1
    return json.loads(lines[0])
