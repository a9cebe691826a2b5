#!/usr/bin/env bash
# wedge compare: metric values on tiny images worked out by hand, EXR and PNG inputs
# (written here by an independent writer in Python, including an EXR whose data window
# does not start at the origin), the JSON shape, and --diff output.
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
if ! command -v python3 >/dev/null; then echo "skip: python3 is needed to write test images"; exit 77; fi
make_temp_dir
fail=0

python3 - "$T" <<'PY' || exit 1
import struct, sys, zlib
d = sys.argv[1]

def attr(name, typ, data):
    return name.encode() + b'\0' + typ.encode() + b'\0' + struct.pack('<i', len(data)) + data

def write_exr(path, w, h, chans, origin=(0, 0)):
    """Uncompressed scanline float32 EXR, straight from the file-format description."""
    names = sorted(chans)
    chlist = b''.join(n.encode() + b'\0' + struct.pack('<iB3xii', 2, 0, 1, 1) for n in names) + b'\0'
    x0, y0 = origin
    box = struct.pack('<iiii', x0, y0, x0 + w - 1, y0 + h - 1)
    hdr = (attr('channels', 'chlist', chlist) + attr('compression', 'compression', b'\0')
           + attr('dataWindow', 'box2i', box) + attr('displayWindow', 'box2i', box)
           + attr('lineOrder', 'lineOrder', b'\0') + attr('pixelAspectRatio', 'float', struct.pack('<f', 1))
           + attr('screenWindowCenter', 'v2f', struct.pack('<ff', 0, 0))
           + attr('screenWindowWidth', 'float', struct.pack('<f', 1)) + b'\0')
    head = struct.pack('<ii', 20000630, 2) + hdr
    off = len(head) + 8 * h
    offsets, blocks = [], []
    for y in range(h):
        payload = b''.join(struct.pack('<%df' % w, *chans[n][y * w:(y + 1) * w]) for n in names)
        block = struct.pack('<ii', y0 + y, len(payload)) + payload
        offsets.append(off)
        off += len(block)
        blocks.append(block)
    with open(path, 'wb') as f:
        f.write(head + b''.join(struct.pack('<Q', o) for o in offsets) + b''.join(blocks))

def write_png(path, w, h, codes):
    """8-bit RGB PNG, filter 0 on every row."""
    raw = b''.join(b'\0' + bytes(codes[y * w * 3:(y + 1) * w * 3]) for y in range(h))
    def chunk(t, data):
        return struct.pack('>I', len(data)) + t + data + struct.pack('>I', zlib.crc32(t + data) & 0xffffffff)
    with open(path, 'wb') as f:
        f.write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0))
                + chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))

def rgb_planes(pixels):
    return {'R': [p[0] for p in pixels], 'G': [p[1] for p in pixels], 'B': [p[2] for p in pixels]}

# The 2x1 images of tests/core/test_metrics.c.
ref = [(0.0, 0.5, 1.0), (0.1, 0.2, 2.0)]
test = [(0.1, 0.5, 0.5), (0.1, 0.4, 3.0)]
write_exr(d + '/ref.exr', 2, 1, rgb_planes(ref))
write_exr(d + '/test.exr', 2, 1, rgb_planes(test))
# Same test image, data window at (-3, 5): only the pixels matter.
write_exr(d + '/test_offset.exr', 2, 1, rgb_planes(test), origin=(-3, 5))
# --by edge_px (section 7): a 5x4 pair equal to 1 but for pixels (0, 2) and (2, 1)
edge = [1.0] * 20
write_exr(d + '/edge_ref.exr', 5, 4, {'R': edge, 'G': edge, 'B': edge})
edge[2 * 5 + 0], edge[1 * 5 + 2] = 2.0, 3.0
write_exr(d + '/edge_test.exr', 5, 4, {'R': edge, 'G': edge, 'B': edge})
# NaN and infinity in a reference: counted as 0 in the metrics, and said.
write_exr(d + '/bad_ref.exr', 2, 1, rgb_planes([(float('nan'), 0.5, 1.0), (0.1, float('inf'), 2.0)]))
# A luminance-only EXR is grey.
write_exr(d + '/grey.exr', 2, 1, {'Y': [0.5, 0.25]})
write_exr(d + '/grey_rgb.exr', 2, 1, rgb_planes([(0.5, 0.5, 0.5), (0.25, 0.25, 0.25)]))
# PNGs with codes 0 and 255 only, which decode to exactly 0 and 1.
write_png(d + '/white.png', 2, 2, [255] * 12)
write_png(d + '/one_black.png', 2, 2, [255] * 9 + [0] * 3)
write_exr(d + '/white.exr', 2, 2, rgb_planes([(1.0, 1.0, 1.0)] * 4))
PY

check_json() { # check_json FILE PYTHON-ASSERTIONS (j is the parsed object)
  python3 - "$1" "$2" <<'PY'
import json, math, sys
text = open(sys.argv[1]).read()
def no_constants(c):
    raise ValueError('non-finite constant ' + c)
j = json.loads(text, parse_constant=no_constants)  # exactly one object, nothing else
assert isinstance(j, dict), text
assert sorted(j) == sorted(['relmse', 'mse', 'rmse', 'psnr', 'ssim', 'nonfinite', 'nonfinite_ref']), j
srgb = lambda x: 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055
near = lambda a, b, tol=1e-6: abs(a - b) <= tol
exec(sys.argv[2])
PY
}

# 0. A reference with non-finite values is reported (both pixels), not silently zeroed.
"$WEDGE" compare "$T/bad_ref.exr" "$T/test.exr" --json > "$T/out.json" 2>"$T/err.txt" || { echo "FAIL: compare exit $?"; fail=1; }
check_json "$T/out.json" 'assert j["nonfinite_ref"] == 2 and j["nonfinite"] == 0, j' || { echo "FAIL: nonfinite_ref"; fail=1; }
grep -qx "wedge compare: warning: $T/bad_ref.exr has 2 pixels with NaN or infinite values (counted as 0)" "$T/err.txt" ||
    { echo "FAIL: no warning for a reference with NaN: $(cat "$T/err.txt")"; fail=1; }

# 1. The hand-worked 2x1 example (see tests/core/test_metrics.c for the arithmetic).
#    SSIM: the 2x1 image is narrower than the window, which shrinks to 1x1: per pixel
#    (2ab + C1)/(a^2 + b^2 + C1) on the luma of the clamped sRGB-encoded pixels.
"$WEDGE" compare "$T/ref.exr" "$T/test.exr" --json > "$T/out.json" || { echo "FAIL: compare exit $?"; fail=1; }
check_json "$T/out.json" '
assert near(j["relmse"], 0.382816885180), j
assert near(j["mse"], 1.3 / 6), j
assert near(j["rmse"], math.sqrt(1.3 / 6)), j
assert near(j["psnr"], 10 * math.log10(20)), j
assert j["nonfinite"] == 0, j
luma = lambda p: sum(w * srgb(min(max(c, 0), 1)) for w, c in zip((0.2126, 0.7152, 0.0722), p))
ref = [(0.0, 0.5, 1.0), (0.1, 0.2, 2.0)]; test = [(0.1, 0.5, 0.5), (0.1, 0.4, 3.0)]
C1 = 1e-4
s = [(2 * luma(r) * luma(t) + C1) / (luma(r) ** 2 + luma(t) ** 2 + C1) for r, t in zip(ref, test)]
assert near(j["ssim"], sum(s) / 2), (j, s)
' || { echo "FAIL: hand-worked EXR example"; fail=1; }

# 2. A data window away from the origin reads as the same pixels.
"$WEDGE" compare "$T/test.exr" "$T/test_offset.exr" --json > "$T/out.json" || { echo "FAIL: offset exit"; fail=1; }
check_json "$T/out.json" 'assert j["mse"] == 0 and j["relmse"] == 0 and j["psnr"] == 100 and j["ssim"] == 1, j' \
  || { echo "FAIL: data window origin"; fail=1; }

# 3. Y-only EXR equals its grey RGB version.
"$WEDGE" compare "$T/grey.exr" "$T/grey_rgb.exr" --json > "$T/out.json" || { echo "FAIL: grey exit"; fail=1; }
check_json "$T/out.json" 'assert j["mse"] == 0, j' || { echo "FAIL: Y channel"; fail=1; }

# 4. PNG inputs (decoded from sRGB; codes 0/255 are exactly 0/1). One black pixel of four:
#    MSE = 3/12 = 0.25, relMSE = 3 (1/1.01) / 12, PSNR = 10 log10(4). SSIM: 2x2 shrinks the
#    window to 1x1: three pixels give 1, the black one (0 + C1)/(1 + C1).
for pair in "white.png one_black.png" "white.exr one_black.png"; do
  set -- $pair
  "$WEDGE" compare "$T/$1" "$T/$2" --json > "$T/out.json" || { echo "FAIL: png exit ($pair)"; fail=1; }
  check_json "$T/out.json" '
assert near(j["mse"], 0.25), j
assert near(j["relmse"], 3 / 1.01 / 12), j
assert near(j["psnr"], 10 * math.log10(4)), j
assert near(j["ssim"], (3 + 1e-4 / (1 + 1e-4)) / 4), j
' || { echo "FAIL: PNG example ($pair)"; fail=1; }
done

# 5. Identical images: zero error, PSNR at its 100 dB cap, SSIM 1.
"$WEDGE" compare "$T/ref.exr" "$T/ref.exr" --json > "$T/out.json" || { echo "FAIL: identical exit"; fail=1; }
check_json "$T/out.json" 'assert j["relmse"] == 0 and j["mse"] == 0 and j["rmse"] == 0 and j["psnr"] == 100 and j["ssim"] == 1, j' \
  || { echo "FAIL: identical"; fail=1; }

# 6. --diff writes PNG and EXR maps of the right size; identical images give a black map.
"$WEDGE" compare "$T/ref.exr" "$T/test.exr" --diff "$T/diff.exr" > "$T/out.txt" || { echo "FAIL: diff exr exit"; fail=1; }
grep -q '^relMSE ' "$T/out.txt" || { echo "FAIL: text output"; cat "$T/out.txt"; fail=1; }
"$WEDGE" compare "$T/diff.exr" "$T/diff.exr" --json > "$T/out.json" || { echo "FAIL: diff.exr unreadable"; fail=1; }
"$WEDGE" compare "$T/ref.exr" "$T/test.exr" --json --diff "$T/diff.png" > "$T/out.json" || { echo "FAIL: diff png exit"; fail=1; }
check_json "$T/out.json" 'assert j["mse"] > 0' || { echo "FAIL: --json with --diff is not one object"; fail=1; }
"$WEDGE" compare "$T/white.png" "$T/white.exr" --diff "$T/black.png" --json > /dev/null || { echo "FAIL: black diff exit"; fail=1; }
"$WEDGE" compare "$T/one_black.png" "$T/black.png" --json > "$T/out.json" 2>&1 || { echo "FAIL: black.png unreadable"; fail=1; }
# black.png is all zeros: against one_black (three white pixels), MSE = 9/12.
check_json "$T/out.json" 'assert near(j["mse"], 0.75), j' || { echo "FAIL: identical images should give a black map"; fail=1; }

# 7. --by edge_px (computed, not a channel): a 5x4 pair equal to 1 but for an edge pixel (0, 2)
#    at 2 and an inner one (2, 1) at 3. Bins < 1 (the outermost ring: 20 - 3x2 = 14 pixels, all at
#    distance 0) and >= 1 (the 6 inner ones, all at distance 1); errors 1/1.01 and 4/1.01 per
#    channel, so the ring holds 1/5 of relMSE.
"$WEDGE" compare "$T/edge_ref.exr" "$T/edge_test.exr" --json --by edge_px --bins 1 > "$T/out.json" \
  || { echo "FAIL: --by edge_px exit"; fail=1; }
python3 - "$T/out.json" <<'PY' || { echo "FAIL: --by edge_px"; fail=1; }
import json, sys
j = json.load(open(sys.argv[1]))
near = lambda a, b, tol=1e-6: abs(a - b) <= tol
b = j["by"]["bins"]
assert j["by"]["channel"] == "edge_px" and len(b) == 2, j
assert b[0]["pixels"] == 14 and b[0]["mean"] == 0 and near(b[0]["relmse_share"], 0.2), j
assert b[1]["pixels"] == 6 and b[1]["mean"] == 1 and near(b[1]["relmse_share"], 0.8), j
assert near(b[0]["relmse"], 1 / 1.01 / 14) and near(b[1]["relmse"], 4 / 1.01 / 6), j
PY

[ $fail -eq 0 ] && echo "compare_metrics: all passed"
exit $fail
