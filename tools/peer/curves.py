"""Time to error: relMSE against seconds for wedge's methods and the peers, on one bench scene.

Every method's error is measured against one wedge reference (Owen-scrambled Sobol', --ref-spp,
its own seed; Mitsuba agrees with wedge at the noise floor, agree.py). Times:
- wedge: `seconds_total` of the render report (parse, BVH, tracing, filtering: what a user
  of `wedge render` waits for, minus process start);
- Mitsuba 3 `path`: the second mi.render at that spp (kernels compiled by the first: JIT
  excluded, scene loading excluded);
- wedge MC + OIDN: the `--aovs` render's seconds_total plus the denoise (device created once
  and warmed up; the filters' commit and execute counted; with auxiliaries the albedo and the
  normal are prefiltered first and counted).
The machine may be shared: each repetition runs every method and point once, interleaved, and
the median time over repetitions is kept (errors: the mean over repetitions, each of its own seed).
"""
import csv
import json
import math
import os
import statistics
import subprocess
import tempfile

import numpy as np

from . import runners

METHOD_STYLE = {
    "wedge mc": ("tab:gray", "o"), "wedge aaf": ("tab:blue", "s"), "wedge lr": ("tab:cyan", "v"),
    "wedge maaf": ("tab:purple", "<"), "wedge fsf": ("tab:brown", ">"),
    "mitsuba path": ("tab:red", "^"), "mc + oidn": ("tab:green", "D"), "mc + oidn (albedo, normal)": ("tab:olive", "P"),
}


def _effects(wedge, scene):
    out = subprocess.run([wedge, "info", scene, "--json"], check=True, capture_output=True, text=True).stdout
    info = json.loads(out)
    eff = info.get("effects", {})
    if isinstance(eff, dict):
        return [k for k, v in eff.items() if v]
    return list(eff)


# Every wedge filter beside Monte Carlo and auto, in the wide table's column order.
WEDGE_FILTERS = ("aaf", "lr", "maaf", "fsf")


def _filters(wedge, scene, effects):
    """The filters that take at least one of the scene's effects (`wedge info --filters`) and
    accept the scene (FSF refuses scenes without a planar area light: a 4x4 probe render)."""
    out = subprocess.run([wedge, "info", "--filters", "--json"], check=True, capture_output=True, text=True).stdout
    takes = {m["name"]: set(m["effects"]) for m in json.loads(out)["methods"]}
    names = []
    for name in WEDGE_FILTERS:
        if not takes.get(name, set()) & set(effects):
            continue
        with tempfile.TemporaryDirectory() as tmp:
            r = subprocess.run([wedge, "render", scene, "--filter", name, "--res", "4x4", "--spp", "1", "--quiet",
                                "-o", os.path.join(tmp, "probe.exr")], capture_output=True, text=True)
        if r.returncode == 0:
            names.append(name)
        else:
            last = r.stderr.strip().splitlines()[-1] if r.stderr.strip() else f"exit {r.returncode}"
            print(f"curves: wedge {name} left out: {last}", flush=True)
    return names


def reference(args, out):
    path = os.path.join(out, "reference.exr")
    if not os.path.exists(path):
        print(f"curves: rendering the reference ({args.ref_spp} spp, Sobol', seed 1000)", flush=True)
        runners.wedge_render(args.wedge, args.scene, path, args.res, args.ref_spp, 1000, sampler="sobol")
    return runners.rgb_of(runners.read_exr(path))


def run(args):
    out = args.out
    os.makedirs(os.path.join(out, "images"), exist_ok=True)
    ref = reference(args, out)
    spps = [int(s) for s in args.spp.split(",")]
    effects = _effects(args.wedge, args.scene)
    # wedge auto: the default a user gets (the choice per effect, issue 18)
    points = [("wedge mc", s) for s in spps] + [("wedge auto", s) for s in spps]
    for name in _filters(args.wedge, args.scene, effects):
        points += [("wedge " + name, s) for s in spps]
    points += [("mitsuba path", s) for s in spps] + [("mc + oidn", s) for s in spps] + \
              [("mc + oidn (albedo, normal)", s) for s in spps]
    ms = None
    try:
        ms = runners.MitsubaScene(args.scene, args.res, workdir=out)
    except Exception as e:  # noqa: BLE001  (an unmapped scene: measured without Mitsuba)
        print(f"curves: no Mitsuba curve: {e}")
        points = [p for p in points if p[0] != "mitsuba path"]
    den = runners.Denoiser()
    warm = np.ones((args.res[1], args.res[0], 3), np.float32)
    den.denoise(warm)
    den.denoise(warm, warm, warm)
    samples = {p: [] for p in points}
    for rep in range(args.repeats):
        for k, (method, x) in enumerate(points):
            seed = 1 + rep * 1000 + k
            img_path = os.path.join(out, "images", f"{method.replace(' ', '_').replace('(', '').replace(')', '').replace(',', '')}-{x:g}.exr")
            spp_avg = x
            if method.startswith("wedge "):
                # --spp under a filter is the frame's average budget (default mu); mc: --filter none
                filt = "none" if method == "wedge mc" else method.split()[1]
                rep_ = runners.wedge_render(args.wedge, args.scene, img_path, args.res, int(x), seed, filt=filt)
                img, secs, spp_avg = runners.rgb_of(runners.read_exr(img_path)), rep_["seconds_total"], rep_["spp_avg"]
            elif method == "mitsuba path":
                img, secs = ms.render_warm(int(x), seed)
                if rep == 0:
                    runners.write_exr(img_path, img)
            else:
                rep_ = runners.wedge_render(args.wedge, args.scene, img_path, args.res, int(x), seed, aovs=True)
                ch = runners.read_exr(img_path)
                color = runners.rgb_of(ch)
                if method == "mc + oidn":
                    img, dsecs = den.denoise(color)
                else:
                    albedo = runners.rgb_of(ch, "albedo.")
                    normal = np.stack([ch["N.X"], ch["N.Y"], ch["N.Z"]], axis=2)
                    img, dsecs = den.denoise(color, albedo, normal)
                secs = rep_["seconds_total"] + dsecs
                if rep == 0:
                    runners.write_exr(img_path.replace(".exr", "-denoised.exr"), img)
            bad = int(np.count_nonzero(~np.isfinite(img)))
            if bad:
                raise RuntimeError(f"{method} {x}: {bad} non-finite values")
            e = runners.relmse(img, ref)
            samples[(method, x)].append((secs, e, spp_avg))
            print(f"curves: rep {rep + 1} {method:28s} {x:>6g}: {secs:8.3f} s  relMSE {e:.3e}  spp {spp_avg:g}", flush=True)
    rows = []
    for (method, x), v in samples.items():
        rows.append({"scene": os.path.splitext(os.path.basename(args.scene))[0], "res": f"{args.res[0]}x{args.res[1]}",
                     "method": method, "x": x, "spp_avg": statistics.mean(s[2] for s in v),
                     "seconds": statistics.median(s[0] for s in v), "relmse": statistics.mean(s[1] for s in v),
                     "repeats": len(v)})
    with open(os.path.join(out, "curves.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    plot(rows, out)
    print(report([out]))


def _curves(rows):
    by = {}
    for r in rows:
        by.setdefault(r["method"], []).append((float(r["seconds"]), float(r["relmse"]), float(r["spp_avg"])))
    for m in by:
        by[m].sort(key=lambda t: t[0])
    return by


def plot(rows, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    by = _curves(rows)
    scene, res = rows[0]["scene"], rows[0]["res"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for m, pts in by.items():
        color, marker = METHOD_STYLE.get(m, ("k", "x"))
        axes[0].loglog([p[0] for p in pts], [p[1] for p in pts], marker=marker, color=color, label=m)
        sp = sorted(pts, key=lambda p: p[2])
        axes[1].loglog([p[2] for p in sp], [p[1] for p in sp], marker=marker, color=color, label=m)
    target = target_error(by)
    for ax in axes:
        if target:
            ax.axhline(target, color="k", lw=0.6, ls=":")
        ax.set_ylabel("relMSE")
        ax.grid(True, which="both", lw=0.3)
    axes[0].set_xlabel("seconds (2 threads, shared machine)")
    axes[1].set_xlabel("samples per pixel (average)")
    axes[0].legend(fontsize=8)
    fig.suptitle(f"{scene}, {res}: error against time and samples (dotted: 64-spp Monte Carlo's error)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, f"peers-{scene}-{res}.png"), dpi=90)
    plt.close(fig)


def time_at(pts, err):
    """Seconds a curve needs to reach relMSE err: log-log linear interpolation between its
    bracketing points, else the nearest end segment extended (flagged)."""
    pts = sorted(pts, key=lambda p: p[0])
    lx = [math.log(p[0]) for p in pts]
    ly = [math.log(p[1]) for p in pts]
    le = math.log(err)
    for i in range(len(pts) - 1):
        if (ly[i] - le) * (ly[i + 1] - le) <= 0 and ly[i] != ly[i + 1]:
            t = (le - ly[i]) / (ly[i + 1] - ly[i])
            return math.exp(lx[i] + t * (lx[i + 1] - lx[i])), False
    if len(pts) < 2:
        return float("nan"), True
    i = 0 if abs(ly[0] - le) < abs(ly[-1] - le) else len(pts) - 2
    if ly[i + 1] == ly[i] or (ly[i + 1] - ly[i]) * (lx[i + 1] - lx[i]) >= 0:
        return float("nan"), True  # error not falling with time there: no estimate
    t = (le - ly[i]) / (ly[i + 1] - ly[i])
    return math.exp(lx[i] + t * (lx[i + 1] - lx[i])), True


def target_error(by):
    mc = by.get("wedge mc")
    if not mc:
        return None
    for s, e, spp in mc:
        if spp == 64:
            return e
    return None


def report(dirs):
    lines = ["| scene | res | target relMSE (64-spp MC) | method | seconds to target | best wedge / method |",
             "|---|---|---|---|---|---|"]
    for d in dirs:
        with open(os.path.join(d, "curves.csv")) as f:
            rows = list(csv.DictReader(f))
        by = _curves(rows)
        target = target_error(by)
        if target is None:
            continue
        times = {m: time_at(p, target) for m, p in by.items()}
        wedge_best = min((t for m, (t, _) in times.items() if m.startswith("wedge") and not math.isnan(t)),
                         default=float("nan"))
        wedge_best = min((t for m, (t, extra) in times.items() if m.startswith("wedge") and not extra
                          and not math.isnan(t)), default=float("nan"))
        for m, (t, extra) in times.items():
            first = min(by[m], key=lambda p: p[0])
            if all(p[1] <= target for p in by[m]):
                # below the target already at its cheapest point: an upper bound on the time
                ratio = f">= {wedge_best / first[0]:.2f}" if not math.isnan(wedge_best) else "-"
                lines.append(f"| {rows[0]['scene']} | {rows[0]['res']} | {target:.2e} | {m} | <= {first[0]:.3f} "
                             f"(below the target at {first[2]:g} spp) | {ratio} |")
                continue
            if extra or math.isnan(t):
                lines.append(f"| {rows[0]['scene']} | {rows[0]['res']} | {target:.2e} | {m} | not reached in the sweep | - |")
                continue
            lines.append(f"| {rows[0]['scene']} | {rows[0]['res']} | {target:.2e} | {m} | {t:.3f} | {wedge_best / t:.2f} |")
    return "\n".join(lines)


def _time_cell(pts, target):
    """(text, seconds or None, kind): kind '=' interpolated, '<=' an upper bound, '>' not reached."""
    first = min(pts, key=lambda p: p[0])
    if all(p[1] <= target for p in pts):
        return f"<= {first[0]:.2f}", first[0], "<="
    t, extra = time_at(pts, target)
    if extra or math.isnan(t):
        return "not reached", None, ">"
    return f"{t:.2f}", t, "="


def report_wide(dirs):
    """One row per scene: seconds to the 64-spp Monte Carlo error per method, and each wedge
    filter's time over each peer's (< 1: the wedge filter is faster)."""
    wedge_methods = ["wedge mc", "wedge auto"] + ["wedge " + f for f in WEDGE_FILTERS]
    peers = ["mitsuba path", "mc + oidn", "mc + oidn (albedo, normal)"]
    head = ["scene", "res", "target relMSE"] + [f"{m} s" for m in wedge_methods + peers] + \
           [f"{w.split()[1]} / {p}" for w in wedge_methods[1:] for p in peers]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for d in dirs:
        with open(os.path.join(d, "curves.csv")) as f:
            rows = list(csv.DictReader(f))
        by = _curves(rows)
        target = target_error(by)
        if target is None:
            continue
        cells = {m: _time_cell(by[m], target) if m in by else ("-", None, "-") for m in wedge_methods + peers}
        out = [rows[0]["scene"], rows[0]["res"], f"{target:.2e}"] + [cells[m][0] for m in wedge_methods + peers]
        for w in wedge_methods[1:]:
            for p in peers:
                tw, kw = cells[w][1], cells[w][2]
                tp, kp = cells[p][1], cells[p][2]
                if tw is None or tp is None:
                    out.append("-")
                elif kw == "=" and kp == "=":
                    out.append(f"{tw / tp:.2f}")
                elif kw == "=" and kp == "<=":
                    out.append(f">= {tw / tp:.2f}")
                elif kw == "<=" and kp == "=":
                    out.append(f"<= {tw / tp:.2f}")
                else:
                    out.append("?")
        lines.append("| " + " | ".join(out) + " |")
    return "\n".join(lines)
