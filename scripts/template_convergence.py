"""Whether a train scene converges (issue 24 item 4): run it at its step,
at half its step and at twice its elements, and print each run's peak
filtered deck acceleration (EN 1991-2 cut-off), peak contact force and
lift-off count, with the change against the first run.

Usage: python3 scripts/template_convergence.py SCENE TAG [base,half,mesh]
(SCENE a built-in name or a TOML file; the runs' scenes and summaries go
to $TMPDIR or /tmp as TAG-*.toml and TAG-*.json).
"""
import json, os, re, subprocess, sys, tempfile, time
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GW = os.path.join(ROOT, "target", "release", "guideway")
OUT = tempfile.gettempdir()
def text_of(scene):
    if os.path.exists(scene):
        return open(scene).read()
    # The built-in's TOML without the annotations --show adds.
    path = os.path.join(ROOT, "src", "scene", "trains", scene + ".toml")
    if os.path.exists(path):
        return open(path).read()
    return subprocess.run([GW, "scenes", "--show", scene], capture_output=True, text=True, check=True).stdout
def edit(text, section, key, fn):
    out, cur = [], None
    for line in text.splitlines():
        m = re.match(r"^\[+([^\]]+)\]+", line)
        if m: cur = m.group(1)
        m2 = re.match(rf"^{key}\s*=\s*([-0-9.eE+]+)", line)
        if cur == section and m2:
            line = f"{key} = {fn(float(m2.group(1)))!r}"
        out.append(line)
    return "\n".join(out) + "\n"
def run(text, tag):
    path = os.path.join(OUT, f"{tag}.toml"); open(path, "w").write(text)
    t = time.time()
    r = subprocess.run([GW, "run", path, "-q", "--summary", os.path.join(OUT, f"{tag}.json"), "--max-steps", "5000000"], capture_output=True, text=True)
    if r.returncode != 0:
        return {"tag": tag, "error": (r.stderr or r.stdout)[-300:]}
    d = json.load(open(os.path.join(OUT, f"{tag}.json")))
    pd = d.get("peak_design", {})
    acc = max([abs(v) for k, v in pd.items() if k.endswith("acceleration_filtered")] or [float("nan")])
    raw = max([abs(v) for k, v in pd.items() if k.endswith(".acceleration")] or [float("nan")])
    force = max((d.get("peak_contact_force") or {"-": float("nan")}).values())
    ev = d.get("events", [])
    lifts = sum(1 for e in ev if e["kind"] == "lift_off")
    return {"tag": tag, "acc_f": acc, "acc_raw": raw, "force": force, "lift_offs": lifts, "wall": round(time.time() - t, 1), "steps": d["steps"]}
scene, name = sys.argv[1], sys.argv[2]
which = sys.argv[3].split(",") if len(sys.argv) > 3 else ["base", "half", "mesh"]
base = text_of(scene)
variants = {"base": base, "half": edit(base, "solver", "step", lambda s: s / 2),
            "mesh": edit(base, "beam", "elements", lambda n: int(n) * 2)}
rows = [run(variants[w], f"{name}-{w}") for w in which]
b = rows[0]
for r in rows:
    if "error" in r: print(r); continue
    rel = lambda k: (r[k] / b[k] - 1) * 100 if "error" not in b else float("nan")
    print(f"{r['tag']:28s} acc_f {r['acc_f']:.4f} ({rel('acc_f'):+.2f}%) raw {r['acc_raw']:.3f} force {r['force']/1e3:.1f} kN ({rel('force'):+.2f}%) lift-offs {r['lift_offs']} steps {r['steps']} wall {r['wall']} s", flush=True)
