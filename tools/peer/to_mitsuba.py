"""pbrt-v4 subset (pbrt_subset.Scene) -> Mitsuba 3 scene dictionary.

Conventions that differ between the two renderers, each handled here:
- camera space: pbrt's is left-handed (+x is image right), Mitsuba's maps camera +x to image
  left, so the sensor gets world_from_camera * diag(-1, 1, 1) (else the image is mirrored);
- fov: pbrt-v4 gives it along the shorter image axis: fov_axis 'smaller';
- path depth: pbrt's maxdepth counts bounces after the camera vertex (1 = direct light only),
  Mitsuba's max_depth counts path vertices including the camera's: max_depth = maxdepth + 1;
- BSDFs: pbrt's diffuse reflects on both sides, Mitsuba's on the normal's side only: twosided;
- area lights: both emit on the side of the surface normal, which both compute from the
  winding (p1 - p0) x (p2 - p0); pbrt's `twosided` emitter has no Mitsuba counterpart;
- spot light falloff: pbrt-v4 is smoothstep in cos(theta) between cos(coneangle) and
  cos(coneangle - conedeltaangle), Mitsuba's is linear in theta: we give Mitsuba a hard cone
  (beam_width = cutoff_angle) and project a radial texture that holds pbrt's smoothstep;
- checkerboard: pbrt has a check per unit of (u * uscale, v * vscale) and tex1 where
  floor(s) + floor(t) is even; Mitsuba's has two checks per unit uv and color0 where both
  halves agree: to_uv = scale(uscale / 2, vscale / 2), color0 = tex1;
- pixel filter: a box of one pixel on both sides (wedge's today; Mitsuba rfilter 'box').
"""
import math
import os
import tempfile

import numpy as np

from . import pbrt_subset


class Unmappable(Exception):
    pass


def _rgb(params, name, default):
    t = params.type_of(name)
    if t is None:
        return list(default)
    vals = params.get_list(name)
    if t == "rgb":
        return [float(v) for v in vals[:3]]
    if t == "float":
        return [float(vals[0])] * 3
    raise Unmappable(f"parameter '{name}' of type '{t}' (only rgb and float are mapped)")


class Converter:
    def __init__(self, scene, mi, res=None, spp=16, seed=0, sampler="stratified", workdir=None):
        self.scene = scene
        self.mi = mi
        self.res = res
        self.spp = spp
        self.seed = seed
        self.sampler = sampler
        self.workdir = workdir or tempfile.mkdtemp(prefix="peer-mitsuba-")
        self.mesh_count = 0

    def _T(self, m):
        return self.mi.ScalarTransform4f(np.asarray(m, dtype=np.float64).tolist())

    # ---- textures and materials ---------------------------------------------------------
    def _spectrum(self, params, name, default):
        if params.type_of(name) == "texture":
            tname = params.get_one(name)
            if tname not in self.scene.textures:
                raise Unmappable(f"texture '{tname}' is not defined")
            cls, tp = self.scene.textures[tname]
            if cls == "checkerboard":
                if int(tp.get_one("dimension", 2)) != 2:
                    raise Unmappable("3D checkerboard texture")
                if tp.get_one("mapping", "uv") != "uv":
                    raise Unmappable("checkerboard with a mapping other than uv")
                su, sv = float(tp.get_one("uscale", 1)), float(tp.get_one("vscale", 1))
                du, dv = float(tp.get_one("udelta", 0)), float(tp.get_one("vdelta", 0))
                # pbrt: s = su u + du; Mitsuba checks flip every half unit, so halve the map
                to_uv = np.array([[su / 2, 0, 0, du / 2], [0, sv / 2, 0, dv / 2], [0, 0, 1, 0], [0, 0, 0, 1]])
                return {"type": "checkerboard",
                        "color0": {"type": "rgb", "value": self._tex_rgb(tp, "tex1", [1, 1, 1])},
                        "color1": {"type": "rgb", "value": self._tex_rgb(tp, "tex2", [0, 0, 0])},
                        "to_uv": self._T(to_uv)}
            raise Unmappable(f"texture class '{cls}' (mapped: checkerboard)")
        return {"type": "rgb", "value": _rgb(params, name, default)}

    def _tex_rgb(self, params, name, default):
        if params.type_of(name) == "texture":
            raise Unmappable("nested textures")
        return _rgb(params, name, default)

    def bsdf(self, material):
        name, params = material
        if name == "diffuse":
            inner = {"type": "diffuse", "reflectance": self._spectrum(params, "reflectance", [0.5] * 3)}
        elif name in ("interface", ""):
            return None
        else:
            raise Unmappable(f"material '{name}' (mapped: diffuse)")
        return {"type": "twosided", "bsdf": inner}

    # ---- shapes -------------------------------------------------------------------------
    def _write_ply(self, P, idx, uv):
        """A binary little-endian PLY that Mitsuba reads as is (no welding, no uv flip)."""
        path = os.path.join(self.workdir, f"mesh{self.mesh_count}.ply")
        self.mesh_count += 1
        nv, nf = len(P), len(idx)
        with open(path, "wb") as f:
            head = ["ply", "format binary_little_endian 1.0", f"element vertex {nv}",
                    "property float x", "property float y", "property float z"]
            if uv is not None:
                head += ["property float u", "property float v"]
            head += [f"element face {nf}", "property list uchar int vertex_indices", "end_header"]
            f.write(("\n".join(head) + "\n").encode())
            vert = np.hstack([P, uv]) if uv is not None else P
            f.write(vert.astype("<f4").tobytes())
            faces = np.zeros(nf, dtype=[("n", "u1"), ("i", "<i4", 3)])
            faces["n"] = 3
            faces["i"] = idx
            f.write(faces.tobytes())
        return path

    def shape(self, sh):
        t, p, m = sh["type"], sh["params"], sh["world_from_object"]
        if sh["moving"]:
            raise Unmappable("moving shapes (motion blur: Mitsuba 3 has no shape motion)")
        if t == "trianglemesh":
            P = np.array(p.get_list("P"), float).reshape(-1, 3)
            idx = p.get_list("indices")
            idx = np.arange(len(P)) if idx is None else np.array(idx, int)
            idx = idx.reshape(-1, 3)
            uv = p.get_list("uv")
            uv = None if uv is None else np.array(uv, float).reshape(-1, 2)
            if p.get_list("N") is not None or p.get_list("S") is not None:
                raise Unmappable("trianglemesh with shading normals")
            # Mitsuba takes the mesh in world space so that the winding (hence the normal)
            # does not depend on whether to_world swaps handedness; pbrt flips the normal of
            # a mesh whose transform swaps handedness, which the winding flip below repeats.
            Pw = (m[:3, :3] @ P.T).T + m[:3, 3]
            flip = (np.linalg.det(m[:3, :3]) < 0) != sh["reverse"]
            if flip:
                idx = idx[:, [0, 2, 1]]
            d = {"type": "ply", "filename": self._write_ply(Pw, idx, uv), "face_normals": True}
        elif t == "sphere":
            r = float(p.get_one("radius", 1.0))
            for k, default in (("zmin", -r), ("zmax", r), ("phimax", 360.0)):
                if abs(float(p.get_one(k, default)) - default) > 1e-6:
                    raise Unmappable("partial spheres (zmin, zmax, phimax)")
            d = {"type": "sphere", "radius": r, "center": [0, 0, 0], "to_world": self._T(m)}
            if sh["reverse"] != (np.linalg.det(m[:3, :3]) < 0):
                d["flip_normals"] = True
        else:
            raise Unmappable(f"shape '{t}' (mapped: trianglemesh, sphere)")
        b = self.bsdf(sh["material"])
        if b is not None:
            d["bsdf"] = b
        if sh["area_light"] is not None:
            lname, lp = sh["area_light"]
            if lname != "diffuse":
                raise Unmappable(f"area light '{lname}'")
            if lp.get_one("twosided", False):
                raise Unmappable("two-sided area lights (Mitsuba's area emitter is one-sided)")
            if lp.get_one("filename") is not None:
                raise Unmappable("image area lights")
            s = float(lp.get_one("scale", 1.0))
            L = [s * c for c in _rgb(lp, "L", [1, 1, 1])]
            d["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": L}}
        return d

    # ---- lights -------------------------------------------------------------------------
    def _spot_texture(self, cone_deg, delta_deg, n=1024):
        """Radial map in Mitsuba's spot uv ((x/z)/tan(cutoff) * 0.5 + 0.5) of pbrt-v4's
        smoothstep falloff, so that Mitsuba's hard cone times this texture is pbrt's spot."""
        c = (np.arange(n) + 0.5) / n
        u, v = np.meshgrid(c, c)
        tan_cut = math.tan(math.radians(cone_deg))
        tan_th = np.hypot(2 * u - 1, 2 * v - 1) * tan_cut
        cos_th = 1.0 / np.sqrt(1.0 + tan_th * tan_th)
        lo, hi = math.cos(math.radians(cone_deg)), math.cos(math.radians(cone_deg - delta_deg))
        if hi <= lo:
            f = (cos_th > lo).astype(float)
        else:
            t = np.clip((cos_th - lo) / (hi - lo), 0, 1)
            f = t * t * (3 - 2 * t)
        img = np.repeat(f[:, :, None], 3, axis=2).astype(np.float32)
        return {"type": "bitmap", "bitmap": self.mi.Bitmap(img), "raw": True, "filter_type": "bilinear",
                "wrap_mode": "clamp"}

    def light(self, l):
        t, p, m = l["type"], l["params"], l["world_from_light"]
        s = float(p.get_one("scale", 1.0))
        if p.get_one("power") is not None:
            raise Unmappable("lights given by 'power'")

        def pt(name, default):
            v = p.get_list(name, default)
            return (m @ np.array(list(v) + [1.0]))[:3]

        if t == "point":
            return {"type": "point", "position": pt("from", [0, 0, 0]).tolist(),
                    "intensity": {"type": "rgb", "value": [s * c for c in _rgb(p, "I", [1, 1, 1])]}}
        if t == "distant":
            d = pt("to", [0, 0, 1]) - pt("from", [0, 0, 0])
            return {"type": "directional", "direction": (d / np.linalg.norm(d)).tolist(),
                    "irradiance": {"type": "rgb", "value": [s * c for c in _rgb(p, "L", [1, 1, 1])]}}
        if t == "spot":
            frm, to = pt("from", [0, 0, 0]), pt("to", [0, 0, 1])
            cone, delta = float(p.get_one("coneangle", 30.0)), float(p.get_one("conedeltaangle", 5.0))
            d = to - frm
            up = [0, 1, 0] if abs(d[1]) < 0.99 * np.linalg.norm(d) else [1, 0, 0]
            return {"type": "spot", "cutoff_angle": cone, "beam_width": cone,
                    "to_world": self.mi.ScalarTransform4f().look_at(origin=frm.tolist(), target=to.tolist(), up=up),
                    "intensity": {"type": "rgb", "value": [s * c for c in _rgb(p, "I", [1, 1, 1])]},
                    "texture": self._spot_texture(cone, delta)}
        if t == "infinite":
            if p.get_one("filename") is not None:
                raise Unmappable("image infinite lights (pbrt-v4's equal-area map)")
            return {"type": "constant", "radiance": {"type": "rgb", "value": [s * c for c in _rgb(p, "L", [1, 1, 1])]}}
        raise Unmappable(f"light '{t}' (mapped: point, spot, distant, constant infinite, diffuse area)")

    # ---- camera, film, integrator --------------------------------------------------------
    def sensor(self):
        name, p, camera_from_world = self.scene.camera
        if name != "perspective":
            raise Unmappable(f"camera '{name}' (mapped: perspective, with or without a thin lens)")
        flip = np.diag([-1.0, 1.0, 1.0, 1.0])  # Mitsuba camera +x is image left
        to_world = np.linalg.inv(camera_from_world) @ flip
        film = self.scene.film
        w, h = self.res or (int(film.get_one("xresolution", 1280)), int(film.get_one("yresolution", 720)))
        if p.get_one("screenwindow") is not None or p.get_one("frameaspectratio") is not None:
            raise Unmappable("screenwindow / frameaspectratio")
        d = {"type": "perspective", "fov": float(p.get_one("fov", 90.0)), "fov_axis": "smaller",
             "to_world": self._T(to_world), "near_clip": 1e-3, "far_clip": 1e5,
             "film": {"type": "hdrfilm", "width": w, "height": h, "rfilter": {"type": "box"},
                      "pixel_format": "rgb", "component_format": "float32"},
             "sampler": {"type": self.sampler, "sample_count": self.spp, "seed": self.seed}}
        lens = float(p.get_one("lensradius", 0.0))
        if lens > 0:
            d["type"] = "thinlens"
            d["aperture_radius"] = lens
            d["focus_distance"] = float(p.get_one("focaldistance", 1e6))
        if float(p.get_one("shutteropen", 0)) != float(p.get_one("shutterclose", 1)) and self.scene.camera[2] is None:
            pass
        return d

    def integrator(self):
        name, p = self.scene.integrator
        if name not in ("path", "volpath"):
            raise Unmappable(f"integrator '{name}' (mapped: path)")
        maxdepth = int(p.get_one("maxdepth", 5))
        return {"type": "path", "max_depth": maxdepth + 1, "rr_depth": maxdepth + 2, "hide_emitters": False}

    def convert(self):
        if self.scene.unmapped:
            raise Unmappable("; ".join(self.scene.unmapped))
        d = {"type": "scene", "integrator": self.integrator(), "sensor": self.sensor()}
        for k, sh in enumerate(self.scene.shapes):
            d[f"shape{k}"] = self.shape(sh)
        for k, l in enumerate(self.scene.lights):
            d[f"light{k}"] = self.light(l)
        return d


def unmapped_reasons(path):
    """Why a scene cannot be given to Mitsuba exactly ([] when it can)."""
    sc = pbrt_subset.parse_file(path)
    if sc.unmapped:
        return list(sc.unmapped)
    return []


def scene_dict(path, mi, res=None, spp=16, seed=0, sampler="stratified", workdir=None):
    sc = pbrt_subset.parse_file(path)
    return Converter(sc, mi, res=res, spp=spp, seed=seed, sampler=sampler, workdir=workdir).convert()
