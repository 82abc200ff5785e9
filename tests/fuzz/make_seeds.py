#!/usr/bin/env python3
"""Writes the seed corpora of tests/fuzz/corpus/ (hand-made, small; run again after editing).

Valid inputs of each format plus near-valid ones (a byte count off, a header field out of
range, a truncated body) that take the parsers down their error paths. The regression inputs
of fixed findings are kept in the corpora under names starting with "crash-" and are not
written here."""
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
SEP = "\n#~~next-file~~\n"  # fuzz_support.hpp kPartSeparator


def put(target, name, data):
    d = os.path.join(HERE, "corpus", target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


# --- calibration (docs/camera-models.md's example) and OCamCalib ---
CALIB = """[rgb]
width = 640
height = 480
fx = 525.0
fy = 525.0
cx = 319.5
cy = 239.5

[rgb.distortion]
k1 = 0.2624
k2 = -0.9531
p1 = -0.0054
p2 = 0.0026
k3 = 1.1633

[fisheye]
model = "kannala_brandt"
width = 1024
height = 1024
fx = 308.8
fy = 308.8
cx = 511.5
cy = 511.5
k = [0.0312, -0.0147, 0.0052, -0.0011]
max_theta = 1.658

[extrinsics]
T_rig_rgb = {translation = [0.0, 0.0, 0.0], rotation_xyzw = [0.0, 0.0, 0.0, 1.0]}
T_rig_fisheye = {translation = [0.0, -0.05, 0.02], rotation_xyzw = [-0.7071067811865476, 0.0, 0.0, 0.7071067811865476]}
depth_baseline_m = 0.075
"""
CALIB_OCAM_INLINE = CALIB.split("[fisheye]")[0] + """[fisheye]
model = "ocam"
width = 640
height = 480
cx = 240.0
cy = 320.0
c = 1.0
d = 0.0
e = 0.0
pol = [-200, 0, 0.0015]
invpol = [365, 200]
"""
CALIB_OCAM_FILE = CALIB.split("[fisheye]")[0] + """[fisheye]
model = "ocam"
file = "ocam.txt"
width = 640
height = 480
"""
OCAM_TXT = """#polynomial coefficients for the DIRECT mapping function (ocam_model.ss in MATLAB). These are used by cam2world

5 -2.245327e+02 0.000000e+00 1.826845e-03 -1.590143e-06 3.867296e-09

#polynomial coefficients for the inverse mapping function (ocam_model.invpol in MATLAB). These are used by world2cam

9 335.563412 199.213420 -10.226317 24.357281 15.082010 -7.096591 -2.140710 1.913124 0.586337

#center: "row" and "column", starting from 0 (C convention)

239.500000 319.500000

#affine parameters "c", "d", "e"

1.000000 0.000000 0.000000

#image size: "height" and "width"

480 640
"""
put("calibration", "example.toml", CALIB)
put("calibration", "rgb_only.toml", CALIB.split("[fisheye]")[0])
put("calibration", "ocam_inline.toml", CALIB_OCAM_INLINE)
put("calibration", "ocam_file.toml", CALIB_OCAM_FILE + SEP + OCAM_TXT)
put("calibration", "ocam_file_short.toml", CALIB_OCAM_FILE + SEP + OCAM_TXT.split("#center")[0])
put("calibration", "huge_size.toml", CALIB.replace("width = 640", "width = 4294967296"))
put("calibration", "bad_quaternion.toml",
    CALIB.replace("rotation_xyzw = [0.0, 0.0, 0.0, 1.0]", "rotation_xyzw = [0.0, 0.0, 0.0, 0.0]"))

# --- service config and board file ---
CONFIG = """# a service on the sim, as docs/configuration.md shows
[source]
rig = "sim"

[http]
address = "127.0.0.1"
port = 8080
jpeg_quality = 80

[pipeline]
no_signal_after_ms = 250

[[object]]
model = "pawn"
position = [0.0, 0.0, 0.0]
"""
BOARD = """[about]
name = "fuzzboard"
summary = "a board file laid under the config"

[source]
rig = "sim"

[bracket]
mains_hz = 50
gpio_chip = "gpiochip0"
gpio_line = 17
strobe_chip = "gpiochip0"
strobe_line = 27
strobe_edge = "rising"

[http]
address = "0.0.0.0"
port = 8080

[display]
enabled = false
"""
put("service_config", "sim.toml", CONFIG)
put("service_config", "empty.toml", "")
put("service_config", "with_board.toml", 'board = "board.toml"\n' + CONFIG + SEP + BOARD)
put("service_config", "board_dir.toml", 'board = "./"\n[http]\nport = 0\n' + SEP + BOARD)
put("service_config", "port_wraps.toml", "[http]\nport = 4294975616\n")
put("service_config", "unknown_key.toml", "[http]\nprot = 8080\n")
put("service_config", "outputs.toml", """[rtsp]
enabled = true
path = "/probeless"

[display]
enabled = true
mode = "1920x1080@60"

[output]
dir = "frames"
format = "png"
""")
for name in ("rpi5", "rk3588", "x86-pocl"):
    src = os.path.join(HERE, "..", "..", "board", name, "board.toml")
    if os.path.exists(src):
        with open(src) as f:
            put("service_config", "board_" + name + ".toml", 'board = "board.toml"\n' + SEP + f.read())

# --- recording ---
MANIFEST = """format = "probeless-recording"
version = 1

[created]
utc = "2026-11-26T12:00:00Z"
by = "probeless 0.1.0"
source = "sim"

[rgbd]
frames = 2

[fisheye]
frames = 1
"""
SMALL_CALIB = """[rgb]
width = 32
height = 24
fx = 30.1
fy = 30.2
cx = 15.5
cy = 11.5

[fisheye]
model = "kannala_brandt"
width = 16
height = 16
fx = 4.8
fy = 4.8
cx = 7.5
cy = 7.5
k = [0.0, 0.0, 0.0, 0.0]
max_theta = 1.658
"""
RGBD = ("sequence,timestamp_ns,color,depth,truth,truth_depth,truth_mask,truth_light,truth_pose\n"
        "100,5000000123,c0.png,d0.png,1,t0.png,t0.png,l0.pfm,1\n"
        "101,5020000123,c0.png,d0.png,0,,,,0\n")
FISHEYE = ("sequence,timestamp_ns,raw,bit_depth,black_level,exposure_time_s,gain_db,bracket_level,"
           "cycle_position,cycle,truth,truth_depth,truth_mask,truth_light,truth_pose\n"
           "7,5003000123,f0.png,12,64,0.001,0,0,0,3,1,,,l0.pfm,1\n")
GT = "# timestamp tx ty tz qx qy qz qw\n5.000000123 0.1 0.2 0.3 0 0 0 1\n"
FGT = "5.003000123 0 0 0 0 0 0.7071067811865476 0.7071067811865476\n"
put("recording", "complete", SEP.join([MANIFEST, SMALL_CALIB, RGBD, FISHEYE, GT, FGT]))
put("recording", "no_fisheye", SEP.join([MANIFEST.replace("frames = 1", "frames = 0"), SMALL_CALIB,
                                         RGBD.replace(",1\n", ",0\n").replace("1,t0.png,t0.png,l0.pfm", "0,,,"),
                                         FISHEYE.split("\n")[0] + "\n"]))
put("recording", "count_mismatch", SEP.join([MANIFEST.replace("frames = 2", "frames = 3"), SMALL_CALIB,
                                             RGBD, FISHEYE, GT, FGT]))
put("recording", "missing_manifest", "")
# Version 2 (docs/formats.md "Power loss"): complete, and interrupted (manifest without
# counts, the last index and trajectory lines cut short, a pose past the last indexed frame).
MANIFEST_V2 = MANIFEST.replace("version = 1\n", "version = 2\ncomplete = true\n")
put("recording", "v2_complete", SEP.join([MANIFEST_V2, SMALL_CALIB, RGBD, FISHEYE, GT, FGT]))
MANIFEST_V2_OPEN = MANIFEST_V2.replace("complete = true", "complete = false").split("[rgbd]")[0]
put("recording", "v2_interrupted",
    SEP.join([MANIFEST_V2_OPEN, SMALL_CALIB, RGBD + "102,50400001",
              FISHEYE.replace(",0,0,0,3,", ",low,0,3,") + "8,5018",
              GT + "5.040000123 0.1 0.2 0.3 0 0 0 1\n5.06", FGT]))
put("recording", "bad_row", SEP.join([MANIFEST, SMALL_CALIB,
                                      RGBD + "102,-1,../c0.png,d0.png,2,,,,0\n", FISHEYE, GT, FGT]))

# --- TUM ---
RGB_TXT = ("# color images\n# file: 'rgbd_dataset_freiburg1_xyz.bag'\n# timestamp filename\n"
           "1305031102.175304 rgb/1.png\n1305031102.211214 rgb/2.png\n1305031102.243211 rgb/3.png\n")
DEPTH_TXT = ("# depth maps\n# timestamp filename\n"
             "1305031102.160407 depth/1.png\n1305031102.194330 depth/2.png\n1305031102.226738 depth/3.png\n")
TUM_GT = ("# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n"
          "1305031098.6659 1.3563 0.6305 1.6380 0.6132 0.5962 -0.3311 -0.3986\n"
          "1305031098.6758 1.3543 0.6306 1.6360 0.6129 0.5966 -0.3316 -0.3980\n"
          "1305031102.2000 1.3500 0.6300 1.6300 0.6100 0.5900 -0.3300 -0.3900\n")
put("tum", "freiburg_like", SEP.join([RGB_TXT, DEPTH_TXT, TUM_GT]))
put("tum", "no_truth", SEP.join([RGB_TXT, DEPTH_TXT]))
put("tum", "escape", SEP.join(["1.0 ../rgb/1.png\n", DEPTH_TXT]))
put("tum", "bad_time", SEP.join(["99999999999999999999.1 rgb/1.png\n1e5 rgb/2.png\n", DEPTH_TXT]))


# --- PNG ---
def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


def png(width, height, bit_depth, colour_type, rows, extra=b"", interlace=0):
    raw = b"".join(b"\0" + r for r in rows)
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, interlace)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + extra + chunk(b"IDAT", zlib.compress(raw))
            + chunk(b"IEND", b""))


put("png", "rgb8.png", png(4, 3, 8, 2, [bytes(range(i * 12, i * 12 + 12)) for i in range(3)]))
put("png", "gray8.png", png(5, 2, 8, 0, [b"\x00\x40\x80\xc0\xff"] * 2))
put("png", "depth16.png", png(3, 2, 16, 0, [struct.pack(">HHH", 0, 1000, 65535)] * 2))
put("png", "rgb16.png", png(2, 2, 16, 2, [struct.pack(">HHHHHH", 1, 2, 3, 4, 5, 6)] * 2))
put("png", "rgba8.png", png(2, 2, 8, 6, [b"\x10\x20\x30\xff\x40\x50\x60\x80"] * 2))
put("png", "palette.png", png(4, 2, 2, 3, [b"\x1b"] * 2, extra=chunk(b"PLTE", b"\xff\0\0\0\xff\0\0\0\xff\xff\xff\xff")
                              + chunk(b"tRNS", b"\x80")))
put("png", "interlaced.png", png(3, 3, 8, 0, [b"\x01\x02\x03"] * 3, interlace=1))
put("png", "huge_claim.png", png(65535, 65535, 8, 2, [b""]))
put("png", "truncated.png", png(8, 8, 8, 2, [b"\x07" * 24] * 8)[:60])

# --- PFM and the light cubemap ---
put("pfm", "gray_le.pfm", b"Pf\n3 2\n-1.0\n" + struct.pack("<6f", 0, 1, 2, 3, 4, float("inf")))
put("pfm", "gray_be.pfm", b"Pf\n2 2\n1.0\n" + struct.pack(">4f", 0.5, 1.5, 2.5, 3.5))
put("pfm", "colour.pfm", b"PF\n1 1\n-1.0\n" + struct.pack("<3f", 1, 2, 3))
put("pfm", "huge.pfm", b"Pf\n65536 65536\n-1.0\n")
put("pfm", "short.pfm", b"Pf\n4 4\n-1.0\n" + struct.pack("<3f", 1, 2, 3))
put("light_cubemap", "n1_le.pfm", b"PF\n1 6\n-1.0\n" + struct.pack("<18f", *range(18)))
put("light_cubemap", "n2_be.pfm", b"PF\n2 12\n1.0\n" + struct.pack(">72f", *[0.25 * i for i in range(72)]))
put("light_cubemap", "huge.pfm", b"PF\n4096 24576\n-1.0\n")
put("light_cubemap", "not_cube.pfm", b"PF\n2 6\n-1.0\n" + struct.pack("<36f", *range(36)))


# --- Radiance RGBE ---
def rgbe_flat(w, h):
    return (b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y %d +X %d\n" % (h, w)
            + bytes([128, 64, 32, 129]) * (w * h))


def rgbe_rle(w, h):
    out = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w)
    for _ in range(h):
        out += bytes([2, 2, w >> 8, w & 255])
        for c in range(4):
            out += bytes([128 + w, 100 + c])  # one run of w
    return out


put("radiance", "flat.hdr", rgbe_flat(3, 2))
put("radiance", "rle.hdr", rgbe_rle(8, 2))
put("radiance", "rle_literal.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n"
    + bytes([2, 2, 0, 8]) + b"".join(bytes([8]) + bytes(range(c, c + 8)) for c in range(4)))
put("radiance", "huge.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16384 +X 16384\n")
put("radiance", "exposure_tiny.hdr", rgbe_flat(1, 1).replace(b"EXPOSURE=1.0", b"EXPOSURE=1e-300\nEXPOSURE=1e-300"))
put("radiance", "plus_y.hdr", rgbe_flat(2, 2).replace(b"-Y 2 +X 2", b"+Y 2 -X 2"))


# --- OpenEXR (uncompressed scanlines, written by hand) ---
def exr(width, height, channels, pixel_type=1, compression=0, values=None):
    def attr(name, kind, body):
        return name + b"\0" + kind + b"\0" + struct.pack("<i", len(body)) + body
    chl = b"".join(c + b"\0" + struct.pack("<iB3xii", pixel_type, 0, 1, 1) for c in channels) + b"\0"
    box = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header = (attr(b"channels", b"chlist", chl) + attr(b"compression", b"compression", bytes([compression]))
              + attr(b"dataWindow", b"box2i", box) + attr(b"displayWindow", b"box2i", box)
              + attr(b"lineOrder", b"lineOrder", b"\0") + attr(b"pixelAspectRatio", b"float", struct.pack("<f", 1))
              + attr(b"screenWindowCenter", b"v2f", struct.pack("<ff", 0, 0))
              + attr(b"screenWindowWidth", b"float", struct.pack("<f", 1)) + b"\0")
    start = 8 + len(header) + 8 * height
    size = 2 if pixel_type == 1 else 4
    blocks, offsets = b"", []
    for y in range(height):
        row = b""
        for ci, _ in enumerate(channels):
            for x in range(width):
                v = (values or (lambda x, y, c: 0.25 * (x + y + c)))(x, y, ci)
                row += struct.pack("<e" if pixel_type == 1 else "<f", v)
        offsets.append(start + len(blocks))
        blocks += struct.pack("<ii", y, len(row)) + row
    return (b"\x76\x2f\x31\x01" + struct.pack("<I", 2) + header
            + b"".join(struct.pack("<Q", o) for o in offsets) + blocks)


put("exr", "half_rgb.exr", exr(3, 2, [b"B", b"G", b"R"]))
put("exr", "float_rgb.exr", exr(2, 2, [b"B", b"G", b"R"], pixel_type=2))
put("exr", "y.exr", exr(2, 3, [b"Y"]))
put("exr", "rgba.exr", exr(2, 1, [b"A", b"B", b"G", b"R"]))
put("exr", "no_rgb.exr", exr(2, 1, [b"Z"]))
put("exr", "truncated.exr", exr(4, 4, [b"B", b"G", b"R"])[:-20])

# --- glTF (JSON with a data: buffer) and GLB ---
import base64
import json

positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
indices = struct.pack("<3H", 0, 1, 2) + b"\0\0"
buf = positions + indices


def gltf(extra_accessor=None, count=3, buffer_uri=True):
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [0, 0, 0.1]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.1, 1.0]}}],
        "buffers": [{"byteLength": len(buf)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
    }
    if buffer_uri:
        doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(buf).decode()
    return doc


put("gltf", "triangle.gltf", json.dumps(gltf(), indent=1))
put("gltf", "huge_count.gltf", json.dumps(gltf(count=6148914691236517206)))
put("gltf", "count_2_27.gltf", json.dumps(gltf(count=1 << 27)))
doc = gltf(buffer_uri=False)
js = json.dumps(doc).encode()
js += b" " * (-len(js) % 4)
binchunk = buf + b"\0" * (-len(buf) % 4)
glb = (b"glTF" + struct.pack("<II", 2, 12 + 8 + len(js) + 8 + len(binchunk))
       + struct.pack("<I", len(js)) + b"JSON" + js + struct.pack("<I", len(binchunk)) + b"BIN\0" + binchunk)
put("gltf", "triangle.glb", glb)

# --- OBJ with a material library ---
OBJ = """mtllib m.mtl
o quad
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vn 0 0 1
usemtl red
f 1/1/1 2/2/1 3/3/1 4/1/1
usemtl blue
f -1 -2 -3
"""
MTL = "newmtl red\nKd 0.8 0.1 0.1\nnewmtl blue\nKd 0.1 0.1 0.8\n"
put("obj", "quad.obj", OBJ + SEP + MTL)
put("obj", "no_mtl.obj", OBJ.replace("mtllib m.mtl\n", ""))
put("obj", "bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\nf 0 1 2\nf -9 1 2\n")

# --- HTTP requests ---
def req(line, *headers):
    return (line + "\r\n" + "".join(h + "\r\n" for h in headers) + "\r\n").encode()


put("http", "root", req("GET / HTTP/1.1", "Host: 127.0.0.1:8080"))
put("http", "status", req("GET /status HTTP/1.1", "Host: localhost", "Connection: close"))
put("http", "snapshot", req("GET /snapshot HTTP/1.0"))
put("http", "action_snapshot", req("GET /?action=snapshot HTTP/1.1", "Host: [::1]:8080"))
put("http", "stream", req("GET /stream HTTP/1.1", "Host: 127.0.0.1"))
put("http", "auth_basic", req("GET /status HTTP/1.1", "Host: localhost",
                              "Authorization: Basic " + base64.b64encode(b"fuzz:fuzz").decode()))
put("http", "auth_bad", req("GET /status HTTP/1.1", "Authorization: Basic !!!!"))
put("http", "bad_host", req("GET /snapshot HTTP/1.1", "Host: evil.example"))
put("http", "origin", req("GET /status HTTP/1.1", "Host: localhost", "Origin: https://dashboard.local"))
put("http", "pipelined", req("GET /status HTTP/1.1", "Host: localhost") + req("GET /snapshot HTTP/1.1", "Host: localhost"))
put("http", "post", b"POST /status HTTP/1.1\r\nHost: localhost\r\nContent-Length: 5\r\n\r\nhello")
put("http", "chunked", b"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n5\r\nhello\r\n0\r\n\r\n")
put("http", "not_found", req("GET /../../etc/passwd HTTP/1.1", "Host: localhost"))
put("http", "garbage", b"\x00\xff\r\n\r\n")
# What a ustreamer client sends (issue #22 item 2) and a Prometheus scrape (item 3).
put("http", "state", req("GET /state HTTP/1.1", "Host: localhost"))
put("http", "metrics", req("GET /metrics HTTP/1.1", "Host: localhost", "Accept: text/plain"))
put("http", "head_snapshot", req("HEAD /snapshot HTTP/1.1", "Host: localhost"))
put("http", "options_preflight", req("OPTIONS /stream HTTP/1.1", "Host: localhost",
                                     "Origin: https://kvm.local",
                                     "Access-Control-Request-Method: GET"))
put("http", "stream_ustreamer", req("GET /stream?key=a%20b&extra_headers=1&advance_headers=yes"
                                    "&dual_final_frames=1&extra_headers=&key HTTP/1.1",
                                    "Host: localhost", "Connection: close"))
