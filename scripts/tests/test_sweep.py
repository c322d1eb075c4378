"""scripts/sweep.py on a small grid: one table, statuses, one FMU
extraction per worker, local cluster and --scheduler."""

import sys

import pandas as pd
import pytest
from distributed import Client, LocalCluster

from conftest import ROOT, WHEEL, fmu_path

sys.path.insert(0, str(ROOT / "scripts"))

import sweep  # noqa: E402

SPEEDS = "10,60,117,250"


@pytest.fixture(scope="module")
def cluster():
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as c:
        yield c


def test_grid_is_every_combination():
    cases = sweep.grid([5.0, 10.0], [1e9, 2e9], [3000.0])
    assert len(cases) == 4
    assert {tuple(c.values()) for c in cases} == {
        (v, ei, 3000.0) for v in (5.0, 10.0) for ei in (1e9, 2e9)}
    assert sweep.parse_range("5:300:5")[-1] == 300.0 and len(sweep.parse_range("5:300:5")) == 60


def test_sweep_on_an_existing_scheduler(cluster, tmp_path):
    out, png = tmp_path / "sweep.csv", tmp_path / "sweep.png"
    sweep.main([str(fmu_path(WHEEL)), "--speeds", SPEEDS, "--stiffness", "1e9",
                "--mass", "3000,6000", "--scheduler", cluster.scheduler_address,
                "--out", str(out), "--plot", str(png)])
    table = pd.read_csv(out)
    assert len(table) == 8
    assert png.read_bytes().startswith(b"\x89PNG")
    ref = table[(table["wheel.initial_speed"] == 10) & (table["wheel.mass"] == 3000)].iloc[0]
    # the paper's beam at 10 m/s: peak midspan deflection 1.093 x static
    assert ref["status"] == "exited"
    assert ref["static_deflection"] == pytest.approx(0.1728)
    assert ref["amplification"] == pytest.approx(1.0927, abs=2e-4)
    assert ref["time_reached"] == pytest.approx(2.2749, abs=1e-3)
    # near the critical speed (117 m/s) the amplification is largest
    exited = table[(table["status"] == "exited") & (table["wheel.mass"] == 3000)]
    assert exited["amplification"].max() > 1.3
    # a lift-off is an event of the run, not its end (unilateral contact):
    # every run reaches the exit, with the time it reached
    assert set(table["status"]) == {"exited"}
    assert (table["time_reached"] > 0).all()


def test_one_fmu_extraction_per_worker(cluster):
    with Client(cluster) as client:
        cases = sweep.grid([20.0, 40.0, 60.0, 80.0, 100.0, 120.0, 20.0, 20.0], [1e9], [3000.0])
        table = sweep.sweep(client, str(fmu_path(WHEEL)), cases, chunk=2)
    assert len(table) == 8 and (table["status"] == "exited").all()
    # each worker process extracted the FMU once and reused it for its runs
    per_worker = table.groupby("pid")["extract_dir"].nunique()
    assert (per_worker == 1).all()
    assert table["extract_dir"].nunique() == table["pid"].nunique() <= 2
    assert table.groupby("pid").size().max() >= 2
    # the instance is reset between runs: the same case, run three times
    # (after other cases), gives the same answer to the last bit
    repeated = table[table["wheel.initial_speed"] == 20.0]
    assert len(repeated) == 3
    assert repeated["peak_deflection"].nunique() == 1
    assert repeated["time_reached"].nunique() == 1


def test_bad_fmu_is_refused_with_a_message(tmp_path, capsys):
    bad = tmp_path / "x.fmu"
    bad.write_text("not a zip")
    with pytest.raises(SystemExit) as e:
        sweep.main([str(bad)])
    assert e.value.code == 2
    assert "not an FMU" in capsys.readouterr().err


def test_sweep_starts_a_local_cluster_without_scheduler(tmp_path, capsys):
    out = tmp_path / "local.csv"
    table = sweep.main([str(fmu_path(WHEEL)), "--speeds", "50,100", "--stiffness", "1e9,2e9",
                        "--mass", "3000", "--workers", "1", "--out", str(out)])
    assert "4 runs on 1 workers" in capsys.readouterr().out
    assert len(pd.read_csv(out)) == 4 and table["pid"].nunique() == 1
    # a stiffer beam deflects less at the same speed
    at = table.set_index(["wheel.initial_speed", "beam.bending_stiffness"])["peak_deflection"]
    assert at[(50.0, 2e9)] < at[(50.0, 1e9)]


def test_non_positive_values_are_refused(capsys):
    with pytest.raises(SystemExit) as e:
        sweep.main([str(fmu_path(WHEEL)), "--speeds", "0,5"])
    assert e.value.code == 2
    assert "--speeds: want values > 0" in capsys.readouterr().err
