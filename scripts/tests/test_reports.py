"""The report scripts (stress table, work-precision plot) run end to end."""

import csv
import subprocess
import sys

from conftest import GUIDEWAY, ROOT


def test_stress_quick_run_has_no_crash_hang_or_non_finite_result(tmp_path):
    out = tmp_path / "stress.md"
    proc = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "stress.py"), "--quick", "--out", str(out),
         "--guideway", str(GUIDEWAY)],
        capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    table = out.read_text()
    rows = [line for line in table.splitlines() if line.startswith("| ") and "outcome" not in line]
    assert len(rows) >= 15
    for row in rows:
        outcome = row.split("|")[2].strip()
        assert outcome in ("exit", "stopped"), row
        if outcome == "stopped":
            # A stop always says why, naming the limit.
            assert "error:" in row, row
    assert "0 crashes, hangs or non-finite results" in proc.stdout


def test_work_precision_quick_run_writes_csv_and_plot(tmp_path):
    proc = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "work_precision.py"), "--quick", "--repeats", "1",
         "--out-dir", str(tmp_path), "--guideway", str(GUIDEWAY)],
        capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    with open(tmp_path / "work_precision.csv", newline="") as f:
        points = list(csv.DictReader(f))
    assert {p["case"] for p in points} == {
        "wheel-10 (2 elements)", "wheel-100 (2 elements)", "wheel-10 (32 elements)"}
    assert {p["scheme"] for p in points} == {
        "rk4", "rk4-quadratic", "hht-0", "hht-0.1", "modal-2", "modal-4", "modal-8", "modal-16"}
    # The modal curves: k modes where the beam has more than k free DOFs.
    modal = {(p["case"], p["scheme"]) for p in points if p["scheme"].startswith("modal")}
    assert ("wheel-10 (2 elements)", "modal-2") in modal
    assert ("wheel-10 (2 elements)", "modal-4") not in modal
    assert ("wheel-10 (32 elements)", "modal-16") in modal
    paper = {p["case"]: p for p in points if p["paper_setting"] == "true"}
    assert len(paper) == 3
    # RK4 at the paper's step runs on the paper's mesh; on 32 elements it is
    # refused (stability limit), which the CSV records instead of a number.
    assert not paper["wheel-10 (2 elements)"]["failure"]
    assert not paper["wheel-100 (2 elements)"]["failure"]
    assert "stability limit" in paper["wheel-10 (32 elements)"]["failure"]
    assert (tmp_path / "work_precision.png").stat().st_size > 10_000
