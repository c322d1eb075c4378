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
    # The CLI stops at the exit (its last row, inside a solver step); the FMU
    # goes on: compare the solver steps before it.
    data = data[:-1]
    result = simulate_fmu(str(fmu_path(WHEEL)), output_interval=float(md.defaultExperiment.stepSize),
                          output=names[1:], stop_time=data[-1, 0])
    compare(result, names, data)


def contact_exit(result):
    """First time in `result` at which `contact.on_beam` is 0."""
    off = np.flatnonzero(result["contact.on_beam"] == 0)
    assert len(off) > 0, "the contact never left the beam"
    return result["time"][off[0]]


def test_the_default_run_goes_past_the_exit_to_its_stop_time():
    """Leaving the structure is an event: fmpy runs the default experiment to
    its stop time, and the exit shows in `contact.on_beam` (issue 12)."""
    md = read_model_description(str(fmu_path(WHEEL)))
    stop = float(md.defaultExperiment.stopTime)
    result = simulate_fmu(str(fmu_path(WHEEL)), output_interval=0.01,
                          output=["contact.position", "contact.on_beam", "wheel.vx"])
    assert result["time"][-1] == pytest.approx(stop, rel=1e-12)
    t_exit = contact_exit(result)
    assert 2.27 < t_exit < 2.28 + 1e-9  # the paper's exit, 2.2749 s, to the output interval
    k = np.flatnonzero(result["time"] == t_exit)[0]
    assert result["contact.position"][k - 1] < 24.0 < result["contact.position"][k]
    assert result["contact.position"][-1] > 24.0 + 9.0 * (stop - t_exit)
    assert np.all(np.isfinite(result["contact.position"]))


def test_exit_statuses_through_the_api(slave):
    """Every step is fmi2OK; the exit is logged under logEvents with its
    exact time; fmi2Terminated stays false."""
    from fmpy.fmi2 import fmi2Terminated
    s = slave(WHEEL, logging_on=True).init()
    s.fmu.setDebugLogging(True, ["logEvents"])
    t, h = 0.0, 0.1
    while t < 3.0 - 1e-9:
        s.fmu.doStep(t, h)  # fmpy raises on anything but fmi2OK
        t += h
    assert not s.fmu.getBooleanStatus(fmi2Terminated)
    events = [m for m in s.messages if "logEvents: event:" in m]
    assert len(events) == 2, s.messages.text()
    assert "Exit of contact" in events[0] and "t = 2.2748781" in events[0]
    assert "LeftTrack of contact" in events[1]
    assert s.fmu.getInteger([s.vr["contact.on_beam"]]) == [0]
    assert s.real("contact.position")[0] > 30.0


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
    # the reference's communication step (a multiple of solver.step for long runs)
    step = native[1, 0] - native[0, 0]
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
    assert "contact.on_beam = 0 from t = 2.28 s" in out
    assert "sensor.midspan.deflection  peak" in out
    assert png.stat().st_size > 10_000


def test_output_interval_a_multiple_of_the_solver_step_matches_every_fourth_row():
    names, data = read_csv(FMU_DIR / "cross-check" / f"{identifier(WHEEL)}_ref.csv")
    step = float(read_model_description(str(fmu_path(WHEEL))).defaultExperiment.stepSize)
    rows = data[::4]
    # the rows on the output grid (the default stop time is not on it)
    on_grid = np.abs(rows[:, 0] / (4 * step) - np.round(rows[:, 0] / (4 * step))) < 1e-6
    rows = rows[on_grid]
    result = simulate_fmu(str(fmu_path(WHEEL)), output_interval=4 * step, output=names[1:],
                          stop_time=rows[-1, 0])
    n = min(len(result), len(rows))
    assert n > 200
    compare(result[:n], names, rows[:n])


def test_any_communication_step_size_is_accepted():
    names, data = read_csv(FMU_DIR / "cross-check" / f"{identifier(WHEEL)}_ref.csv")
    result = simulate_fmu(str(fmu_path(WHEEL)), output_interval=0.007,
                          output=["wheel.x", "sensor.midspan.deflection"])
    assert np.all(np.diff(result["time"][:-1]) == pytest.approx(0.007))
    k = int(round(1.001 / 0.007))  # compare at t = 1.001 s against the native trajectory
    x_native = np.interp(result["time"][k], data[:, 0], data[:, names.index("wheel.x")])
    assert result["wheel.x"][k] == pytest.approx(x_native, rel=1e-4)
