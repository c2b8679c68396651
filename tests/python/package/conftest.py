"""Shared pieces of the Python package's tests: the repository, the command-line binary, and
the fracturing Brazilian disc run once by the command line and once by fdem.run."""

import os
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
EXAMPLES = REPO / "examples"
DISC = EXAMPLES / "brazilian-disc-fracture.json"
ELASTIC = EXAMPLES / "brazilian-disc-elastic.json"


def fdem_bin() -> Path:
    """The command-line binary (`FDEM_BIN`, else target/release/fdem)."""
    p = Path(os.environ.get("FDEM_BIN", REPO / "target" / "release" / "fdem"))
    assert p.exists(), f"{p} is missing: build it with cargo build --release"
    return p


def cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Runs `fdem ARGS` and returns its completed process (text output)."""
    return subprocess.run(
        [str(fdem_bin()), *args], capture_output=True, text=True, check=check, cwd=REPO
    )


def last_file(pvd: Path) -> Path:
    """The last file a .pvd collection lists."""
    files = [d.get("file") for d in ET.parse(pvd).getroot().iter("DataSet")]
    return pvd.parent / files[-1]


@pytest.fixture(scope="session")
def disc_runs(tmp_path_factory):
    """The fracturing disc by `fdem run --out cli` and by `fdem.run(out=py)`, side by side:
    (cli folder, py folder, the Result)."""
    import fdem

    root = tmp_path_factory.mktemp("disc")
    cli_out, py_out = root / "cli", root / "py"
    proc = subprocess.Popen(
        [str(fdem_bin()), "run", str(DISC), "--out", str(cli_out)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        result = fdem.run(DISC, out=py_out, progress=False)
    finally:
        _, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err
    return cli_out, py_out, result
