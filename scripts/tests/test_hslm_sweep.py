"""scripts/hslm_sweep.py on a two-worker local cluster: the envelope joined
from the workers' parts is the one `guideway sweep` writes on one machine,
and the binary reaches each worker once."""

import subprocess
import sys

import pandas as pd
import pytest
from distributed import Client, LocalCluster

from conftest import GUIDEWAY, ROOT

sys.path.insert(0, str(ROOT / "scripts"))

import hslm_sweep  # noqa: E402

SCENE = str(ROOT / "scenes" / "bridge25_hslm.toml")
TRAINS = ["HSLM-A1", "HSLM-A4", "HSLM-A10"]
SPEEDS = "150:350:100"


@pytest.fixture(scope="module")
def cluster():
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as c:
        yield c


def test_the_cluster_gives_the_single_machine_envelope(cluster, tmp_path):
    with Client(cluster) as client:
        table, binaries = hslm_sweep.sweep(client, str(GUIDEWAY), SCENE, TRAINS, SPEEDS, "km/h")
        workers = client.run(lambda dask_worker: dask_worker.local_directory)
    single = tmp_path / "single.csv"
    subprocess.run([str(GUIDEWAY), "sweep", SCENE, "--speeds", SPEEDS, "--unit", "km/h",
                    "--trains", ",".join(TRAINS), "--out", str(single)], check=True,
                   capture_output=True)
    expected = pd.read_csv(single)
    assert len(table) == 9
    assert list(table.columns) == list(expected.columns)
    # The same numbers to the last bit: each part is guideway sweep itself.
    pd.testing.assert_frame_equal(table, expected, check_exact=True)
    # The binary was written into the workers' own directories, once each.
    assert 1 <= len(binaries) <= len(workers)
    assert all(any(b.startswith(d) for d in workers.values()) for b in binaries)


def test_main_writes_the_envelope_and_its_plot(cluster, tmp_path):
    out, png = tmp_path / "envelope.csv", tmp_path / "envelope.png"
    hslm_sweep.main([SCENE, "--speeds", "200:300:50", "--trains", "HSLM-A2,HSLM-A3",
                     "--scheduler", cluster.scheduler_address, "--guideway", str(GUIDEWAY),
                     "--track", "slab", "--out", str(out), "--plot", str(png)])
    table = pd.read_csv(out)
    assert list(table["train"]) == ["HSLM-A2"] * 3 + ["HSLM-A3"] * 3
    assert list(table["speed_km_h"]) == [200, 250, 300] * 2
    assert (table["section.midspan.moment.daf"] > 0.9).all()
    assert png.read_bytes().startswith(b"\x89PNG")


def test_a_bad_train_is_refused(capsys):
    with pytest.raises(SystemExit):
        hslm_sweep.main([SCENE, "--trains", "HSLM-B1", "--guideway", str(GUIDEWAY)])
    assert "'HSLM-B1' is not a train" in capsys.readouterr().err
