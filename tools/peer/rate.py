"""Speed per sample: samples per second of wedge `--filter none` against Mitsuba 3's `path`
integrator on the same scenes, in the same run (issue 22's peer benchmark).

Per scene, ROUNDS rounds, each timing Mitsuba first and then every wedge binary, so that a load
change on the machine hits all of them alike. Mitsuba's time is its warm `mi.render` call (scene
loaded and kernels compiled beforehand: no parse, no JIT, no write). wedge is timed two ways:
the whole process (wall clock: start, parse, BVH build, render, EXR write) and the report's
`seconds_trace` (the render alone, the part Mitsuba's timed call covers). Medians over rounds;
the ratio is Mitsuba's seconds over wedge's, i.e. wedge's samples per second over Mitsuba's at
equal samples.
"""
import os
import statistics
import time

from . import runners


def _wedge_once(wedge, scene, res, spp, seed, workdir, threads):
    """(wall seconds of the whole process, the report's seconds_trace) of one render."""
    t0 = time.perf_counter()
    rep = runners.wedge_render(wedge, scene, os.path.join(workdir, "rate.exr"), res, spp, seed, threads=threads)
    return time.perf_counter() - t0, float(rep["seconds_trace"])


def rate(scenes, wedges, res, spp, rounds, workdir, threads=2, log=print):
    """wedges: {label: binary}. Returns one row per scene with the medians and the ratios."""
    rows = []
    for scene in scenes:
        ms = runners.MitsubaScene(scene, res, workdir=workdir)
        ms.render(spp, 7919)   # compile Mitsuba's kernels at this spp once, outside the timing
        mi_s, w_proc, w_render = [], {k: [] for k in wedges}, {k: [] for k in wedges}
        for r in range(rounds):
            mi_s.append(ms.render(spp, r + 1)[1])
            for label, binary in wedges.items():
                p, t = _wedge_once(binary, scene, res, spp, r + 1, workdir, threads)
                w_proc[label].append(p)
                w_render[label].append(t)
        row = {"scene": os.path.splitext(os.path.basename(scene))[0], "res": f"{res[0]}x{res[1]}",
               "spp": spp, "rounds": rounds, "mitsuba_s": statistics.median(mi_s), "wedge": {}}
        for label in wedges:
            p, t = statistics.median(w_proc[label]), statistics.median(w_render[label])
            row["wedge"][label] = {"process_s": p, "render_s": t,
                                   "ratio_process": row["mitsuba_s"] / p,
                                   "ratio_render": row["mitsuba_s"] / t}
        rows.append(row)
        cells = ", ".join(f"{k} {v['ratio_process']:.2f} / {v['ratio_render']:.2f}"
                          for k, v in row["wedge"].items())
        log(f"{row['scene']:16s} Mitsuba {row['mitsuba_s']:.3f} s; wedge / Mitsuba samples per second "
            f"(process / render alone): {cells}")
    return rows


def table(rows):
    """Markdown: one line per scene, for each wedge binary its seconds and both ratios."""
    labels = list(rows[0]["wedge"]) if rows else []
    head = "| scene | Mitsuba s | " + " | ".join(
        f"{k} process s | {k} render s | **{k} / Mitsuba, process** | render alone" for k in labels) + " |"
    sep = "|---|---:|" + "---:|---:|---:|---:|" * len(labels)
    lines = [head, sep]
    for r in rows:
        cells = " | ".join(f"{v['process_s']:.3f} | {v['render_s']:.3f} | **{v['ratio_process']:.2f}** | "
                           f"{v['ratio_render']:.2f}" for v in r["wedge"].values())
        lines.append(f"| {r['scene']} | {r['mitsuba_s']:.3f} | {cells} |")
    return "\n".join(lines)
