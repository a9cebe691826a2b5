#!/usr/bin/env bash
# wedge compare: usage errors exit 1, unreadable inputs and size mismatches exit 2 with an
# 'error:' line naming the file, write failures exit 3, non-finite pixels are counted and
# never reach the JSON.
set -u
. "$(dirname "$0")/../lib.sh"
require_wedge
if ! command -v python3 >/dev/null; then echo "skip: python3 is needed to write test images"; exit 77; fi
make_temp_dir
fail=0

python3 - "$T" <<'PY' || exit 1
import struct, sys, zlib
d = sys.argv[1]
def chunk(t, data):
    return struct.pack('>I', len(data)) + t + data + struct.pack('>I', zlib.crc32(t + data) & 0xffffffff)
def write_png(path, w, h, codes):
    raw = b''.join(b'\0' + bytes(codes[y * w * 3:(y + 1) * w * 3]) for y in range(h))
    with open(path, 'wb') as f:
        f.write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0))
                + chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))
def attr(name, typ, data):
    return name.encode() + b'\0' + typ.encode() + b'\0' + struct.pack('<i', len(data)) + data
def write_exr(path, w, h, chans):
    names = sorted(chans)
    chlist = b''.join(n.encode() + b'\0' + struct.pack('<iB3xii', 2, 0, 1, 1) for n in names) + b'\0'
    box = struct.pack('<iiii', 0, 0, w - 1, h - 1)
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
        blocks.append(struct.pack('<ii', y, len(payload)) + payload)
        offsets.append(off)
        off += len(blocks[-1])
    with open(path, 'wb') as f:
        f.write(head + b''.join(struct.pack('<Q', o) for o in offsets) + b''.join(blocks))
write_png(d + '/a_2x2.png', 2, 2, [128] * 12)
write_png(d + '/b_3x2.png', 3, 2, [128] * 18)
nan, inf = float('nan'), float('inf')
write_exr(d + '/ref.exr', 3, 1, {'R': [0.5] * 3, 'G': [0.5] * 3, 'B': [0.5] * 3})
write_exr(d + '/nan.exr', 3, 1, {'R': [nan, 0.5, inf], 'G': [0.5, 0.5, -inf], 'B': [0.5] * 3})
write_exr(d + '/z_only.exr', 3, 1, {'Z': [1.0] * 3})
# a test image with a per-pixel key: pixel errors 0, 0.5 and 1.5 against ref.exr
write_exr(d + '/keyed.exr', 3, 1, {'R': [0.5, 1.0, 2.0], 'G': [0.5, 1.0, 2.0], 'B': [0.5, 1.0, 2.0],
                                   'spp': [16.0, 40.0, 100.0]})
open(d + '/text.exr', 'w').write('not an image\n')
PY

expect_exit() { # expect_exit CODE DESCRIPTION -- ARGS...
  local want=$1 what=$2; shift 3
  "$WEDGE" compare "$@" > "$T/stdout" 2> "$T/stderr"
  local got=$?
  if [ $got -ne "$want" ]; then echo "FAIL: $what: exit $got, expected $want"; cat "$T/stderr"; fail=1; return 1; fi
  return 0
}
expect_stderr() { # expect_stderr DESCRIPTION FIXED-STRING
  grep -qF -- "$2" "$T/stderr" || { echo "FAIL: $1: stderr lacks '$2'"; cat "$T/stderr"; fail=1; }
}

# Usage errors: exit 1.
expect_exit 1 "no arguments" --
expect_exit 1 "one image" -- "$T/a_2x2.png"
expect_exit 1 "three images" -- "$T/a_2x2.png" "$T/a_2x2.png" "$T/a_2x2.png"
expect_exit 1 "unknown option" -- "$T/a_2x2.png" "$T/a_2x2.png" --frobnicate && expect_stderr "unknown option" "error: unknown option '--frobnicate'"
expect_exit 1 "--diff without a file" -- "$T/a_2x2.png" "$T/a_2x2.png" --diff
expect_exit 1 "--diff with a bad extension" -- "$T/a_2x2.png" "$T/a_2x2.png" --diff "$T/d.txt" && expect_stderr "bad --diff" "must end in .exr or .png"
expect_exit 0 "--help" -- --help
grep -q '^usage: wedge compare REF TEST' "$T/stdout" || { echo "FAIL: --help text"; fail=1; }

expect_exit 1 "--by without a channel" -- "$T/ref.exr" "$T/keyed.exr" --by && expect_stderr "--by" "error: --by needs a channel name"
expect_exit 1 "--bins not increasing" -- "$T/ref.exr" "$T/keyed.exr" --by spp --bins 4,2 && expect_stderr "--bins order" "error: --bins needs increasing finite numbers"
expect_exit 1 "--bins not numbers" -- "$T/ref.exr" "$T/keyed.exr" --by spp --bins 1,x && expect_stderr "--bins text" "error: --bins needs increasing finite numbers"

# Unreadable inputs: exit 2, 'PATH: error: ...' naming the file.
expect_exit 2 "missing reference" -- "$T/absent.exr" "$T/ref.exr" && expect_stderr "missing reference" "$T/absent.exr: error: cannot open: No such file or directory"
expect_exit 2 "missing test" -- "$T/ref.exr" "$T/absent.png" && expect_stderr "missing test" "$T/absent.png: error: cannot open: No such file or directory"
expect_exit 2 "garbage EXR" -- "$T/ref.exr" "$T/text.exr" && expect_stderr "garbage" "$T/text.exr: error: cannot read EXR"
expect_exit 2 "EXR without colour" -- "$T/ref.exr" "$T/z_only.exr" && expect_stderr "no rgb" "$T/z_only.exr: error: no R, G, B or Y channels (the file has: Z)"

# --by: the channel must exist in TEST (EXR), named with what the file has; nothing on stdout.
expect_exit 2 "--by a missing channel" -- "$T/ref.exr" "$T/keyed.exr" --by aaf.beta_px.shadow && \
  expect_stderr "--by missing" "$T/keyed.exr: error: no channel 'aaf.beta_px.shadow' (the file has: B, G, R, spp)"
[ -s "$T/stdout" ] && { echo "FAIL: --by a missing channel printed metrics"; fail=1; }
expect_exit 2 "--by on a PNG" -- "$T/a_2x2.png" "$T/a_2x2.png" --by spp && \
  expect_stderr "--by png" "$T/a_2x2.png: error: --by needs an EXR test image"

# --by splits relMSE: terms 0, 0.25/0.26 and 2.25/0.26 (each channel alike) in bins < 32,
# [32, 64), >= 64; the shares add up to 1.
expect_exit 0 "--by spp" -- "$T/ref.exr" "$T/keyed.exr" --by spp --bins 32,64 --json
python3 - "$T/stdout" <<'PY' || { echo "FAIL: --by spp breakdown"; fail=1; }
import json, sys
j = json.loads(open(sys.argv[1]).read())
b = j['by']['bins']
assert j['by']['channel'] == 'spp' and len(b) == 3, j
assert b[0]['lo'] is None and b[0]['hi'] == 32 and b[2]['hi'] is None, b
assert [x['pixels'] for x in b] == [1, 1, 1], b
terms = [0.0, 0.25 / 0.26, 2.25 / 0.26]
for x, t in zip(b, terms):
    assert abs(x['relmse'] - t) < 1e-6, (x, t)
    assert abs(x['relmse_share'] - t / sum(terms)) < 1e-6, (x, t)
assert abs(b[1]['mean'] - 40.0) < 1e-9, b
assert abs(j['relmse'] - sum(terms) / 3) < 1e-6, j
PY

# Size mismatch: exit 2, naming both files.
expect_exit 2 "size mismatch" -- "$T/a_2x2.png" "$T/b_3x2.png" && \
  expect_stderr "size mismatch" "$T/b_3x2.png: error: image is 3x2 but the reference $T/a_2x2.png is 2x2"

# Diff that cannot be written: exit 3, and nothing left in the target folder's parent.
expect_exit 3 "diff into a missing folder" -- "$T/ref.exr" "$T/ref.exr" --diff "$T/no/such/d.png" && expect_stderr "diff folder" "error: cannot create a file in folder"

# Non-finite TEST pixels: counted (2 of 3 pixels), replaced by 0 elsewhere, JSON finite.
#   REF 0.5 everywhere; TEST R = (NaN, .5, Inf), G = (.5, .5, -Inf): three values become 0,
#   MSE = 3 * 0.25 / 9.
expect_exit 0 "nan test image" -- "$T/ref.exr" "$T/nan.exr" --json
python3 - "$T/stdout" <<'PY' || { echo "FAIL: non-finite handling"; fail=1; }
import json, sys
def bad(c): raise ValueError(c)
j = json.loads(open(sys.argv[1]).read(), parse_constant=bad)
assert j['nonfinite'] == 2, j
assert abs(j['mse'] - 0.75 / 9) < 1e-7, j
PY

[ $fail -eq 0 ] && echo "compare_errors: all passed"
exit $fail
