"""Running the three renderers being compared: wedge (a subprocess), Mitsuba 3 (in process,
LLVM back end) and wedge Monte Carlo followed by Intel Open Image Denoise (in process)."""
import json
import os
import subprocess
import time

import numpy as np

_MI = None


def mitsuba(threads=2):
    """Import Mitsuba with its LLVM RGB variant (needs DRJIT_LIBLLVM_PATH to an LLVM >= 19)."""
    global _MI
    if _MI is None:
        import drjit as dr
        import mitsuba as mi
        mi.set_variant("llvm_ad_rgb")
        dr.set_thread_count(threads)
        _MI = mi
    return _MI


# ---- images ------------------------------------------------------------------------------
def read_exr(path):
    """All channels of an EXR as {name: HxW float32 array} (names as stored: R, G, B, albedo.R, ...)."""
    mi = mitsuba()
    b = mi.Bitmap(path)
    arr = np.array(b, copy=False).astype(np.float32)
    if arr.ndim == 2:
        arr = arr[:, :, None]
    st = b.struct_()
    names = [st[i].name for i in range(b.channel_count())]
    return {n: arr[:, :, i] for i, n in enumerate(names)}


def rgb_of(channels, prefix=""):
    return np.stack([channels[prefix + c] for c in ("R", "G", "B")], axis=2)


def write_exr(path, rgb):
    mi = mitsuba()
    mi.Bitmap(np.ascontiguousarray(rgb, dtype=np.float32), mi.Bitmap.PixelFormat.RGB).write(path)


def relmse(test, ref):
    """wedge's headline metric (src/core/image_metrics.h): mean over pixels and channels of
    (t - r)^2 / (r^2 + 0.01)."""
    t, r = np.asarray(test, np.float64), np.asarray(ref, np.float64)
    return float(np.mean((t - r) ** 2 / (r * r + 0.01)))


# ---- wedge -------------------------------------------------------------------------------
def wedge_render(wedge, scene, out, res, spp, seed, sampler="stratified", filt="none", mu=None, aovs=False,
                 threads=None):
    cmd = [wedge, "render", scene, "-o", out, "--res", f"{res[0]}x{res[1]}", "--spp", str(spp),
           "--seed", str(seed), "--sampler", sampler, "--filter", filt, "--quiet", "--report", out + ".json"]
    if mu is not None:
        cmd += ["--mu", str(mu)]
    if threads is not None:
        cmd += ["--threads", str(threads)]
    if aovs:
        cmd.append("--aovs")
    subprocess.run(cmd, check=True)
    with open(out + ".json") as f:
        rep = json.load(f)
    if rep.get("nonfinite_pixels", 0):
        raise RuntimeError(f"{out}: {rep['nonfinite_pixels']} non-finite pixels")
    return rep


# ---- Mitsuba 3 -----------------------------------------------------------------------------
class MitsubaScene:
    """A bench scene converted once; renders at any spp and seed."""

    MAX_LANES = 1 << 24   # samples per mi.render call (memory: one JIT lane per sample; passes
    # of fewer samples each are stratified on their own, which costs variance)

    def __init__(self, path, res, sampler="stratified", workdir=None):
        from . import to_mitsuba
        mi = mitsuba()
        self.res = res
        self.scene = mi.load_dict(to_mitsuba.scene_dict(path, mi, res=res, spp=16, sampler=sampler,
                                                        workdir=workdir))

    def render(self, spp, seed):
        """Mean of passes of at most MAX_LANES samples each: (HxWx3 image, seconds)."""
        mi = mitsuba()
        import drjit as dr
        per_pass = max(1, min(spp, self.MAX_LANES // (self.res[0] * self.res[1])))
        # the stratified sampler wants square counts: keep passes square when spp is
        while per_pass > 1 and spp % per_pass:
            per_pass //= 2
        passes = spp // per_pass
        acc = None
        t0 = time.perf_counter()
        for k in range(passes):
            img = mi.render(self.scene, spp=per_pass, seed=seed * 65536 + k)
            dr.eval(img)
            a = np.array(img, dtype=np.float64)
            acc = a if acc is None else acc + a
        secs = time.perf_counter() - t0
        return (acc / passes)[:, :, :3].astype(np.float32), secs

    def render_warm(self, spp, seed):
        """Time of a render whose kernels are compiled already (a first render at the same spp
        with another seed compiles them; Mitsuba's JIT cost is excluded, as the issue asks)."""
        self.render(spp, seed + 7919)
        return self.render(spp, seed)


# ---- Intel Open Image Denoise --------------------------------------------------------------
class Denoiser:
    """OIDN's RT filter, HDR input. With auxiliaries, albedo and normal are denoised first and
    passed as clean (OIDN's recommended 'prefiltered' mode); the time of all passes is counted."""

    def __init__(self, threads=2):
        import pyoidn
        self.oidn = pyoidn
        self.device = pyoidn.Device(pyoidn.OIDN_DEVICE_TYPE_CPU)
        if hasattr(self.device, "set_int"):
            self.device.set_int("numThreads", threads)
        self.device.commit()

    def _run(self, color, albedo=None, normal=None, hdr=True, clean_aux=False):
        o = self.oidn
        out = np.zeros_like(color)
        flt = o.Filter(self.device, o.OIDN_FILTER_TYPE_RT)
        flt.set_image(o.OIDN_IMAGE_COLOR, color, o.OIDN_FORMAT_FLOAT3)
        if albedo is not None:
            flt.set_image(o.OIDN_IMAGE_ALBEDO, albedo, o.OIDN_FORMAT_FLOAT3)
        if normal is not None:
            flt.set_image(o.OIDN_IMAGE_NORMAL, normal, o.OIDN_FORMAT_FLOAT3)
        flt.set_image(o.OIDN_IMAGE_OUTPUT, out, o.OIDN_FORMAT_FLOAT3)
        flt.set_bool("hdr", hdr)
        if clean_aux:
            flt.set_bool("cleanAux", True)
        flt.commit()
        flt.execute()
        err = self.device.get_error()
        flt.release()
        if err:
            raise RuntimeError(f"OIDN: {err}")
        return out

    def _prefilter(self, slot, img):
        """OIDN's documented prefiltering of an auxiliary: the RT filter with only that image."""
        o = self.oidn
        out = np.zeros_like(img)
        flt = o.Filter(self.device, o.OIDN_FILTER_TYPE_RT)
        flt.set_image(slot, img, o.OIDN_FORMAT_FLOAT3)
        flt.set_image(o.OIDN_IMAGE_OUTPUT, out, o.OIDN_FORMAT_FLOAT3)
        flt.commit()
        flt.execute()
        err = self.device.get_error()
        flt.release()
        if err:
            raise RuntimeError(f"OIDN: {err}")
        return out

    def denoise(self, color, albedo=None, normal=None):
        c = np.ascontiguousarray(color, np.float32)
        t0 = time.perf_counter()
        if albedo is None:
            out = self._run(c)
        else:
            a = self._prefilter(self.oidn.OIDN_IMAGE_ALBEDO, np.ascontiguousarray(albedo, np.float32))
            n = self._prefilter(self.oidn.OIDN_IMAGE_NORMAL, np.ascontiguousarray(normal, np.float32))
            out = self._run(c, a, n, clean_aux=True)
        return out, time.perf_counter() - t0
