"""A reader of the pbrt-v4 subset the bench scenes use, for handing them to other renderers.

It keeps what a peer renderer needs (camera, film, integrator depth, shapes with their world
transforms, materials, textures, lights) and records everything it does not understand in
`Scene.unmapped`, so that a converter can refuse a scene instead of rendering a different one.
Transforms follow pbrt-v4: every transform statement post-multiplies the current transform
matrix (CTM); at `Camera` the CTM is camera-from-world; `WorldBegin` resets it to identity.
"""
import math
import os
import re

import numpy as np

_TOKEN = re.compile(r'"[^"]*"|\[|\]|[^\s\[\]"#]+|#[^\n]*')


def tokenize(text):
    for m in _TOKEN.finditer(text):
        tok = m.group(0)
        if tok.startswith("#"):
            continue
        yield tok


def _number(tok):
    try:
        return float(tok)
    except ValueError:
        raise ValueError(f"expected a number, got {tok!r}")


class Params(dict):
    """Parameter list: name -> (type, list of values)."""

    def get_one(self, name, default=None):
        if name not in self:
            return default
        vals = self[name][1]
        return vals[0] if len(vals) == 1 else vals

    def get_list(self, name, default=None):
        return self[name][1] if name in self else default

    def type_of(self, name):
        return self[name][0] if name in self else None


def translate(v):
    m = np.eye(4)
    m[:3, 3] = v
    return m


def scale(v):
    return np.diag([v[0], v[1], v[2], 1.0])


def rotate(angle_deg, axis):
    """Rotation by angle about axis, counter-clockwise looking down the axis (pbrt-v4 Rotate)."""
    a = np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    th = math.radians(angle_deg)
    c, s = math.cos(th), math.sin(th)
    x, y, z = a
    r = np.array([
        [c + (1 - c) * x * x, (1 - c) * x * y - s * z, (1 - c) * x * z + s * y],
        [(1 - c) * x * y + s * z, c + (1 - c) * y * y, (1 - c) * y * z - s * x],
        [(1 - c) * x * z - s * y, (1 - c) * y * z + s * x, c + (1 - c) * z * z],
    ])
    m = np.eye(4)
    m[:3, :3] = r
    return m


def look_at(eye, target, up):
    """pbrt-v4 LookAt: camera-from-world for a camera at eye looking at target. Camera space is
    left-handed: +x is cross(up, dir) (image right), +y up, +z the viewing direction."""
    eye, target, up = (np.asarray(v, float) for v in (eye, target, up))
    d = target - eye
    d /= np.linalg.norm(d)
    right = np.cross(up / np.linalg.norm(up), d)
    if np.linalg.norm(right) == 0:
        raise ValueError("LookAt: up vector and viewing direction are parallel")
    right /= np.linalg.norm(right)
    new_up = np.cross(d, right)
    world_from_camera = np.eye(4)
    world_from_camera[:3, 0] = right
    world_from_camera[:3, 1] = new_up
    world_from_camera[:3, 2] = d
    world_from_camera[:3, 3] = eye
    return np.linalg.inv(world_from_camera)


class Scene:
    def __init__(self):
        self.camera = None          # (type, Params, camera_from_world)
        self.film = Params()
        self.sampler = None
        self.integrator = ("path", Params())
        self.pixel_filter = None
        self.shapes = []            # dicts: type, params, world_from_object, material, area_light, reverse
        self.lights = []            # dicts: type, params, world_from_light
        self.textures = {}          # name -> (class, Params)
        self.named_materials = {}
        self.unmapped = []          # human-readable reasons this scene cannot be converted exactly
        self.base_dir = "."

    def note(self, what):
        if what not in self.unmapped:
            self.unmapped.append(what)


class _State:
    def __init__(self):
        self.ctm = np.eye(4)
        self.ctm_end = np.eye(4)     # the CTM at the shutter's close (ActiveTransform EndTime)
        self.active = "all"
        self.material = ("diffuse", Params())
        self.area_light = None
        self.reverse = False

    def copy(self):
        s = _State()
        s.ctm, s.ctm_end = self.ctm.copy(), self.ctm_end.copy()
        s.active, s.material, s.area_light, s.reverse = self.active, self.material, self.area_light, self.reverse
        return s


def _read_params(toks, i):
    params = Params()
    while i < len(toks) and toks[i].startswith('"'):
        decl = toks[i][1:-1].split()
        if len(decl) != 2:
            break
        ptype, pname = decl
        i += 1
        vals = []
        if toks[i] == "[":
            i += 1
            while toks[i] != "]":
                vals.append(toks[i])
                i += 1
            i += 1
        else:
            vals.append(toks[i])
            i += 1
        if ptype in ("string", "texture", "bool"):
            vals = [v.strip('"') for v in vals]
            if ptype == "bool":
                vals = [v == "true" for v in vals]
        else:
            vals = [_number(v) for v in vals]
        params[pname] = (ptype, vals)
    return params, i


def parse_file(path):
    with open(path) as f:
        text = f.read()
    scene = Scene()
    scene.base_dir = os.path.dirname(os.path.abspath(path))
    toks = list(tokenize(text))
    st = _State()
    stack = []
    i = 0

    def apply(m):
        if st.active in ("all", "start"):
            st.ctm = st.ctm @ m
        if st.active in ("all", "end"):
            st.ctm_end = st.ctm_end @ m

    while i < len(toks):
        d = toks[i]
        i += 1
        if d == "LookAt":
            v = [_number(t) for t in toks[i:i + 9]]
            i += 9
            apply(look_at(v[0:3], v[3:6], v[6:9]))
        elif d == "Translate":
            apply(translate([_number(t) for t in toks[i:i + 3]]))
            i += 3
        elif d == "Scale":
            apply(scale([_number(t) for t in toks[i:i + 3]]))
            i += 3
        elif d == "Rotate":
            v = [_number(t) for t in toks[i:i + 4]]
            i += 4
            apply(rotate(v[0], v[1:4]))
        elif d in ("Transform", "ConcatTransform"):
            assert toks[i] == "["
            v = [_number(t) for t in toks[i + 1:i + 17]]
            i += 18
            m = np.array(v).reshape(4, 4).T  # pbrt lists the matrix column by column
            if d == "Transform":
                if st.active in ("all", "start"):
                    st.ctm = m.copy()
                if st.active in ("all", "end"):
                    st.ctm_end = m.copy()
            else:
                apply(m)
        elif d == "Identity":
            if st.active in ("all", "start"):
                st.ctm = np.eye(4)
            if st.active in ("all", "end"):
                st.ctm_end = np.eye(4)
        elif d == "ActiveTransform":
            st.active = {"All": "all", "StartTime": "start", "EndTime": "end"}[toks[i]]
            i += 1
        elif d == "ReverseOrientation":
            st.reverse = not st.reverse
        elif d in ("Camera", "Film", "Sampler", "Integrator", "PixelFilter", "Shape", "LightSource",
                   "AreaLightSource", "Material", "MakeNamedMaterial", "NamedMaterial", "Texture",
                   "Accelerator", "ColorSpace", "Option", "Attribute", "MakeNamedMedium", "MediumInterface",
                   "CoordinateSystem", "CoordSysTransform", "ObjectBegin", "ObjectInstance", "Include", "Import"):
            name = toks[i].strip('"')
            i += 1
            extra = []
            if d == "Texture":
                extra = [toks[i].strip('"'), toks[i + 1].strip('"')]
                i += 2
            if d == "MediumInterface" and i < len(toks) and toks[i].startswith('"') and len(toks[i].split()) == 1:
                i += 1
            params, i = _read_params(toks, i)
            if d == "Camera":
                scene.camera = (name, params, st.ctm.copy())
                if not np.allclose(st.ctm, st.ctm_end):
                    scene.note("camera motion (Mitsuba 3's perspective sensors take one transform)")
            elif d == "Film":
                scene.film = params
            elif d == "Sampler":
                scene.sampler = (name, params)
            elif d == "Integrator":
                scene.integrator = (name, params)
            elif d == "PixelFilter":
                scene.pixel_filter = (name, params)
            elif d == "Material":
                st.material = (name, params)
            elif d == "MakeNamedMaterial":
                scene.named_materials[name] = (params.get_one("type", "diffuse"), params)
            elif d == "NamedMaterial":
                if name not in scene.named_materials:
                    raise ValueError(f"NamedMaterial '{name}' is not defined")
                st.material = scene.named_materials[name]
            elif d == "Texture":
                scene.textures[name] = (extra[1], params)
                if extra[0] != "spectrum" and extra[0] != "float":
                    scene.note(f"texture type '{extra[0]}'")
            elif d == "AreaLightSource":
                st.area_light = (name, params)
            elif d == "LightSource":
                scene.lights.append({"type": name, "params": params, "world_from_light": st.ctm.copy()})
            elif d == "Shape":
                moving = not np.allclose(st.ctm, st.ctm_end)
                if moving:
                    scene.note("moving shapes (motion blur: Mitsuba 3 has no shape motion)")
                scene.shapes.append({"type": name, "params": params, "world_from_object": st.ctm.copy(),
                                     "material": st.material, "area_light": st.area_light,
                                     "reverse": st.reverse, "moving": moving})
            elif d in ("Accelerator", "ColorSpace", "Option"):
                pass
            else:
                scene.note(f"{d} statements")
        elif d in ("AttributeBegin", "TransformBegin"):
            stack.append(st.copy())
        elif d in ("AttributeEnd", "TransformEnd"):
            restored = stack.pop()
            if d == "TransformEnd":
                st.ctm, st.ctm_end = restored.ctm, restored.ctm_end
            else:
                st = restored
        elif d == "WorldBegin":
            st.ctm = np.eye(4)
            st.ctm_end = np.eye(4)
            st.active = "all"
        elif d == "WorldEnd":
            pass
        else:
            raise ValueError(f"unknown directive {d!r}")
    if scene.camera is None:
        scene.camera = ("perspective", Params(), np.eye(4))
    return scene
