"""Shared fixtures: the repository, the CLI binary the package is compared with, and its
output; the designer's server (`cwsynth serve`) and a page of it in Debian's chromium (the
browser tests: `test_designer*.py`). The CLI is `$CWSYNTH_CLI`, else `target/release/cwsynth` (built from the same
workspace and lock file as the extension; `cargo build --release --bin cwsynth` reuses the
extension's compiled library)."""

import json
import os
import shutil
import subprocess
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PROBLEMS = sorted((REPO / "problems").glob("*.toml"))
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")

# The longest module first: with CI's `pytest -n 2 --dist loadfile` (modules handed out in
# collection order) it starts at once on one worker and the rest share the other.
FIRST = "test_designer_scenes.py"


def pytest_collection_modifyitems(items):
    items.sort(key=lambda it: it.path.name != FIRST)


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


@pytest.fixture(scope="module")
def server():
    """`cwsynth serve problems/` on a free port: its address."""
    p = subprocess.Popen(
        [str(cli_path()), "serve", "--no-open", "--port", "0", str(REPO / "problems")],
        stdout=subprocess.PIPE,
        text=True,
    )
    line = p.stdout.readline()
    assert line.startswith("cwsynth serve: http://"), line
    yield line.split(": ", 1)[1].strip()
    p.terminate()
    p.wait(10)


@pytest.fixture(scope="module")
def page(server):
    """The designer's page in chromium, its first answer drawn; no script error on it."""
    playwright = pytest.importorskip("playwright.sync_api")
    if CHROMIUM is None:
        pytest.skip("no chromium")
    with playwright.sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        pg = b.new_page(accept_downloads=True)
        errors = []
        pg.on("pageerror", lambda e: errors.append(str(e)))
        pg.goto(server)
        pg.wait_for_selector("body[data-solved]")
        yield pg
        assert errors == [], errors
        b.close()


def solved_after(pg, act):
    """Runs `act` and waits for the page's next answer; the time it took (s)."""
    n = pg.get_attribute("body", "data-solved")
    t0 = time.perf_counter()
    act()
    pg.wait_for_selector(f"body:not([data-solved='{n}'])", timeout=120_000)
    return time.perf_counter() - t0
