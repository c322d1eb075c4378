"""Simulation results through FMI match native runs of the same scene."""

import shutil
import subprocess

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

from conftest import (FMU_DIR, GUIDEWAY, SCENES, WHEEL, fmu_path, identifier,
                      native_reference, read_csv, scene_of, set_in_toml)


def compare(result, names, data, rtol=1e-12):
    """fmpy result vs native rows at the same times: every column."""
    t_native = data[:, 0]
    t_fmu = result["time"]
    assert len(t_fmu) == len(t_native), (len(t_fmu), len(t_native))
    np.testing.assert_allclose(t_fmu, t_native, rtol=rtol, atol=1e-12)
    for k, name in enumerate(names[1:], start=1):
        np.testing.assert_allclose(result[name], data[:, k], rtol=rtol, atol=0, err_msg=name)


@pytest.mark.parametrize("scene", SCENES)
def test_fmpy_reproduces_the_native_run_at_every_solver_step(scene):
    names, data = read_csv(FMU_DIR / "cross-check" / f"{identifier(scene)}_ref.csv")
    md = read_model_description(str(fmu_path(scene)))
    step = float(md.defaultExperiment.stepSize)
    result = simulate_fmu(str(fmu_path(scene)), output_interval=step, output=names[1:])
    compare(result, names, data)


def test_fmpy_matches_the_cli_run():
    """`guideway run --out` (the CLI) gives the same numbers as the FMU."""
    help_text = subprocess.run([str(GUIDEWAY), "run", "--help"], capture_output=True,
                               text=True).stdout if GUIDEWAY.is_file() else ""
    if "--out" not in help_text:
        pytest.skip("the guideway CLI with `run --out CSV` is not built on this branch yet")
    out = FMU_DIR / "cli_run.csv"
    subprocess.run([str(GUIDEWAY), "run", WHEEL, "--out", str(out), "--quiet"], check=True)
    names, data = read_csv(out)
    md = read_model_description(str(fmu_path(WHEEL)))
    result = simulate_fmu(str(fmu_path(WHEEL)), output_interval=float(md.defaultExperiment.stepSize),
                          output=names[1:], stop_time=data[-1, 0] + 1.0)
    compare(result, names, data)


def test_exit_is_reported_through_last_successful_time():
    names, data = read_csv(FMU_DIR / "cross-check" / f"{identifier(WHEEL)}_ref.csv")
    exit_time = data[-1, 0]
    md = read_model_description(str(fmu_path(WHEEL)))
    stop = float(md.defaultExperiment.stopTime)
    assert exit_time < stop - 0.1, "the 10 m/s run should leave the beam before the stop time"
    result = simulate_fmu(str(fmu_path(WHEEL)), output_interval=0.01, output=["contact.position"])
    assert result["time"][-1] == pytest.approx(exit_time, rel=1e-9)
    assert result["time"][-1] < stop
    assert result["contact.position"][-1] == pytest.approx(24.0, rel=1e-9)
    assert np.all(np.isfinite(result["contact.position"]))


def test_exit_statuses_through_the_api(slave):
    from fmpy.fmi2 import fmi2Terminated, fmi2LastSuccessfulTime
    from fmpy.fmi1 import FMICallException
    s = slave(WHEEL).init()
    t, h = 0.0, 0.1
    assert not s.fmu.getBooleanStatus(fmi2Terminated)
    with pytest.raises(FMICallException) as e:
        while True:
            s.fmu.doStep(t, h)
            t += h
    assert e.value.status == 2  # fmi2Discard
    assert s.fmu.getBooleanStatus(fmi2Terminated)
    t_exit = s.fmu.getRealStatus(fmi2LastSuccessfulTime)
    assert 2.0 < t_exit < t + h
    assert "end of the beam" in s.messages.text()
    assert s.real("contact.position")[0] == pytest.approx(24.0)
    with pytest.raises(FMICallException):
        s.fmu.doStep(t_exit, h)
    assert "left the beam" in s.messages.text()


PARAMS = [
    ("beam.elements", "beam", "elements", 3),
    ("beam.length", "beam", "length", 30.0),
    ("wheel.initial_speed", "body", "initial_speed", 20.0),
    ("solver.step", "solver", "step", 0.00125),
]


@pytest.mark.parametrize("variable,section,key,value", PARAMS, ids=[p[0] for p in PARAMS])
def test_start_values_change_the_result_as_a_native_run_does(variable, section, key, value,
                                                              tmp_path):
    fmu = str(fmu_path(WHEEL))
    names, native = native_reference(set_in_toml(scene_of(fmu), section, key, value), tmp_path)
    step = value if key == "step" else float(read_model_description(fmu).defaultExperiment.stepSize)
    n = 200  # compare the first 200 solver steps
    stop = native[n, 0]
    result = simulate_fmu(fmu, start_values={variable: value}, output_interval=step,
                          stop_time=stop, output=names[1:])
    compare(result, names, native[: n + 1])
    _, default = read_csv(FMU_DIR / "cross-check" / f"{identifier(WHEEL)}_ref.csv")
    assert not np.array_equal(default[: n + 1], native[: n + 1]), "the value changed nothing"


def test_libcosimpy_agrees_with_fmpy():
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    fmu = str(fmu_path(WHEEL))
    md = read_model_description(fmu)
    names = ["wheel.x", "wheel.vx", "contact.normal_force", "sensor.midspan.deflection"]
    vr = {v.name: v.valueReference for v in md.modelVariables}
    step_ns = 10_000_000  # 0.01 s

    execution = CosimExecution.from_step_size(step_ns)
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    index = execution.add_local_slave(CosimLocalSlave(fmu_path=fmu, instance_name="wheel"))
    assert index == 0
    compared = 0
    result = simulate_fmu(fmu, output_interval=0.01, stop_time=2.0, output=names)
    for k in range(1, 201):
        assert execution.step(), f"libcosim step {k} failed"
        if k % 50 == 0:
            values = observer.last_real_values(0, [vr[n] for n in names])
            for name, value in zip(names, values):
                np.testing.assert_allclose(value, result[name][k], rtol=1e-9, err_msg=name)
            compared += 1
    assert compared == 4


def test_main_job_script_prints_the_summary_and_writes_the_plot(tmp_path, capsys):
    import importlib.util
    from conftest import ROOT
    spec = importlib.util.spec_from_file_location("simulate_fmu_script",
                                                  ROOT / "scripts" / "simulate_fmu.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    png = tmp_path / "plot.png"
    assert script.main([str(fmu_path(WHEEL)), "--interval", "0.01", "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert "fmi2LastSuccessfulTime" in out
    assert "sensor.midspan.deflection  peak" in out
    assert png.stat().st_size > 10_000
