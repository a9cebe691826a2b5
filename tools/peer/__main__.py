"""tools/peer-bench entry point: python -m peer COMMAND ... (see tools/peer-bench --help)."""
import argparse
import json
import os
import sys
import tempfile


def _res(s):
    w, h = s.lower().split("x")
    return int(w), int(h)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="peer-bench", description=(
        "Compare wedge with Mitsuba 3 and with Monte Carlo + Intel Open Image Denoise on the bench scenes."))
    sub = ap.add_subparsers(dest="cmd", required=True)

    c = sub.add_parser("convert", help="print what a scene becomes in Mitsuba 3 (or why it cannot)")
    c.add_argument("scene")

    r = sub.add_parser("render", help="render a scene with Mitsuba 3 (path, warm) to an EXR")
    r.add_argument("scene")
    r.add_argument("-o", "--out", required=True)
    r.add_argument("--res", type=_res, default=(128, 128))
    r.add_argument("--spp", type=int, default=64)
    r.add_argument("--seed", type=int, default=1)

    a = sub.add_parser("agree", help="Mitsuba 3 against wedge at the noise floor")
    a.add_argument("scenes", nargs="+")
    a.add_argument("--wedge", default="build/wedge")
    a.add_argument("--res", type=_res, default=(64, 64))
    a.add_argument("--spp", type=int, default=256)
    a.add_argument("--check", action="store_true",
                   help="exit 1 unless every bias ratio is within [--lo, --hi]")
    a.add_argument("--lo", type=float, default=0.85)
    a.add_argument("--hi", type=float, default=1.15)
    a.add_argument("--seed", type=int, default=1, help="wedge and Mitsuba use seeds SEED and SEED + 1")
    a.add_argument("--keep", help="keep the images in this folder")
    a.add_argument("--json")

    t = sub.add_parser("curves", help="error against time of wedge methods, Mitsuba 3 and MC + OIDN")
    t.add_argument("scene")
    t.add_argument("--wedge", default="build/wedge")
    t.add_argument("--res", type=_res, default=(128, 128))
    t.add_argument("--spp", default="4,16,64,256")
    t.add_argument("--ref-spp", type=int, default=4096)
    t.add_argument("--repeats", type=int, default=3, help="timed repetitions per point (median)")
    t.add_argument("--out", required=True)

    n = sub.add_parser("noise", help="variance per image at equal spp: wedge binaries against Mitsuba 3")
    n.add_argument("scene")
    n.add_argument("--wedge", action="append", required=True, help="LABEL=BINARY (repeatable)")
    n.add_argument("--res", type=_res, default=(64, 64))
    n.add_argument("--spp", default="4,16,64,256,1024")

    sp = sub.add_parser("rate", help="samples per second of wedge --filter none against Mitsuba 3 (issue 22)")
    sp.add_argument("scenes", nargs="+")
    sp.add_argument("--wedge", action="append", help="LABEL=BINARY or BINARY (repeatable; default build/wedge)")
    sp.add_argument("--res", type=_res, default=(256, 256))
    sp.add_argument("--spp", type=int, default=256)
    sp.add_argument("--rounds", type=int, default=3, help="interleaved timed rounds per scene (median)")
    sp.add_argument("--threads", type=int, default=2, help="threads of both renderers")
    sp.add_argument("--json")

    rep = sub.add_parser("report", help="equal-error table (Markdown) from curves folders")
    rep.add_argument("dirs", nargs="+")
    rep.add_argument("--wide", action="store_true", help="one row per scene, ratios of each wedge filter to each peer")

    args = ap.parse_args(argv)
    if args.cmd == "convert":
        from . import pbrt_subset, runners, to_mitsuba
        sc = pbrt_subset.parse_file(args.scene)
        if sc.unmapped:
            print(f"{args.scene}: not mapped to Mitsuba 3: " + "; ".join(sc.unmapped))
            return 2
        mi = runners.mitsuba()
        try:
            d = to_mitsuba.Converter(sc, mi).convert()
        except to_mitsuba.Unmappable as e:
            print(f"{args.scene}: not mapped to Mitsuba 3: {e}")
            return 2
        print(mi.load_dict(d))
        return 0
    if args.cmd == "render":
        from . import runners
        ms = runners.MitsubaScene(args.scene, args.res)
        img, secs = ms.render_warm(args.spp, args.seed)
        runners.write_exr(args.out, img)
        print(f"{args.out}: {args.res[0]}x{args.res[1]}, {args.spp} spp, {secs:.3f} s (warm)")
        return 0
    if args.cmd == "agree":
        from . import agree
        rows, ok = [], True
        with tempfile.TemporaryDirectory(prefix="peer-agree-") as tmp:
            wd = args.keep or tmp
            for s in args.scenes:
                sd = os.path.join(wd, os.path.splitext(os.path.basename(s))[0])
                os.makedirs(sd, exist_ok=True)
                row = agree.agree(s, args.wedge, args.res, args.spp, sd, seed=args.seed)
                rows.append(row)
                if not (args.lo <= row["ratio"] <= args.hi):
                    print(f"FAIL {row['scene']}: bias ratio {row['ratio']:.3f} outside [{args.lo}, {args.hi}]")
                    ok = False
        if args.json:
            with open(args.json, "w") as f:
                json.dump(rows, f, indent=1)
        return 0 if (ok or not args.check) else 1
    if args.cmd == "noise":
        from . import agree
        wedges = dict(w.split("=", 1) for w in args.wedge)
        with tempfile.TemporaryDirectory(prefix="peer-noise-") as wd:
            agree.noise(args.scene, wedges, args.res, [int(s) for s in args.spp.split(",")], wd)
        return 0
    if args.cmd == "rate":
        from . import rate, runners
        runners.mitsuba(args.threads)
        wedges = {}
        for w in args.wedge or ["build/wedge"]:
            label, _, binary = w.rpartition("=")
            wedges[label or "wedge"] = binary
        with tempfile.TemporaryDirectory(prefix="peer-rate-") as wd:
            rows = rate.rate(args.scenes, wedges, args.res, args.spp, args.rounds, wd, args.threads)
        print(rate.table(rows))
        if args.json:
            with open(args.json, "w") as f:
                json.dump(rows, f, indent=1)
        return 0
    if args.cmd == "curves":
        from . import curves
        curves.run(args)
        return 0
    if args.cmd == "report":
        from . import curves
        print(curves.report_wide(args.dirs) if args.wide else curves.report(args.dirs))
        return 0
    return 1


if __name__ == "__main__":
    sys.exit(main())
