#!/usr/bin/env python3
"""Writes the small generated seeds of fuzz/corpus/ (materials with direction records,
PNG images of each colour type and bit depth, OBJ meshes). Run once; the output is
committed. The EXR seeds and the scenes are written by hand or by gonio itself."""
import os, struct, zlib

here = os.path.dirname(os.path.abspath(__file__))
corpus = os.path.join(here, "corpus")

materials = [
    '{"type":"diffuse","reflectance":[0.2,0.4,0.6]}',
    '{"type":"mirror"}',
    '{"type":"conductor","material":"Au"}',
    '{"type":"conductor","fresnel":"schlick","f0":[1,0.8,0.3]}',
    '{"type":"conductor","eta":[0.2,0.9,1.1],"k":[3.9,2.4,2.2]}',
    '{"type":"dielectric","eta":1.5}',
    '{"type":"roughconductor","alpha":[0.05,0.5],"material":"Cu","multiscatter":false}',
    '{"type":"roughconductor","alpha":0.3,"distribution":"beckmann","fresnel":"schlick","f0":1,"multiscatter":true}',
    '{"type":"roughdielectric","alpha":0.2,"eta":1.33,"distribution":"ggx"}',
    '{"type":"roughdielectric","alpha":0.5,"eta":1.5,"multiscatter":true}',
    '{"type":"orennayar","reflectance":0.8,"sigma":20,"model":"full"}',
    '{"type":"phong","kd":0.3,"ks":0.7,"exponent":50}',
    '{"type":"blinnphong","kd":[0.1,0.2,0.3],"ks":0.5,"exponent":200}',
    '{"type":"ward","kd":0.2,"ks":0.8,"alpha":[0.05,0.3]}',
    '{"type":"ashikhminshirley","rd":0.4,"rs":0.1,"nu":10,"nv":1000}',
    '{"type":"plastic","eta":1.5,"reflectance":0.8}',
    '{"type":"plastic","eta":1.5,"reflectance":0.8,"alpha":0.2,"distribution":"beckmann"}',
    '{"type":"blend","weight":0.25,"bsdfs":[{"type":"diffuse"},{"type":"conductor","material":"Ag"}]}',
    '{"type":"sheen","color":[0.9,0.4,0.1],"roughness":0.3}',
    '{"type":"eon","reflectance":[0.9,0.5,0.2],"roughness":0.7}',
    '{"type":"gltf_pbr","metallic":0,"roughness":0.3,"transmission":0.5,"thickness":1,"sheen_color":0.5,"clearcoat":1}',
    '{"type":"roughconductor","alpha":0.2,"fresnel":"f82","f0":[0.95,0.64,0.54],"f82":[0.9,0.6,0.3],"multiscatter":true}',
    '{"type":"layered","top":{"type":"roughdielectric","alpha":0.2,"eta":1.5},"bottom":{"type":"diffuse","reflectance":0.8},"thickness":0.3,"albedo":0.9,"g":0.5,"max_depth":20,"samples":2}',
    '{"type":"layered","top":{"type":"dielectric","eta":1.5},"bottom":{"type":"mirror"},"thickness":0.5}',
    '{"type":"layered","top":{"type":"roughdielectric","alpha":0.3,"eta":1.5},"bottom":{"type":"dielectric","eta":1.2},"thickness":0.2,"albedo":0.5}',
    '{"type":"layered","top":{"type":"thindielectric","eta":1.5,"thin_film":{"thickness":300,"eta":1.33}},"bottom":{"type":"diffuse"},"thickness":0.5,"albedo":0.8,"g":-0.7}',
    '{"type":"thindielectric","eta":1.5}',
    '{"type":"roughdielectric","alpha":0.3,"eta":1.5,"thin_film":{"thickness":400,"eta":1.38}}',
    '{"type":"conductor","material":"Au","thin_film":{"thickness":250,"eta":1.5}}',
]

def record(wo, wi, u, mode):
    return struct.pack("<3f3f3IB3x", *wo, *wi, *[int(x * (1 << 24)) << 8 for x in u], mode)

records = (record((0.3, 0.1, 0.9), (0.6, 0.8, 1e-20), (0.5, 0.2, 0.7), 0)
           + record((1, 0, 1e-40), (0, 1, 1e-40), (0, 0, 0), 1)
           + record((0, 0, 1), (0, 0, -1), (0.999999, 0.999999, 0.999999), 0)
           + record((0.5, 0.5, -0.7), (0.5, 0.5, -0.7), (0.1, 0.9, 0.3), 1))
for i, m in enumerate(materials):
    with open(os.path.join(corpus, "material", f"seed-{i:02d}"), "wb") as f:
        f.write(m.encode() + b"\0" + records)

def png(width, height, bit_depth, color_type, rows, palette=None):
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    raw = b"".join(b"\0" + r for r in rows)
    out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, 0))
    if palette:
        out += chunk(b"PLTE", palette)
    return out + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")

pngs = {
    "rgb8": png(2, 2, 8, 2, [bytes([255, 0, 0, 0, 255, 0]), bytes([0, 0, 255, 128, 128, 128])]),
    "rgba8": png(2, 1, 8, 6, [bytes([10, 20, 30, 255, 40, 50, 60, 0])]),
    "gray16": png(2, 2, 16, 0, [struct.pack(">HH", 0, 65535), struct.pack(">HH", 1000, 30000)]),
    "gray1": png(8, 1, 1, 0, [bytes([0b10110010])]),
    "palette": png(2, 2, 8, 3, [bytes([0, 1]), bytes([1, 0])], palette=bytes([255, 255, 255, 0, 0, 0])),
    "grayalpha8": png(1, 1, 8, 4, [bytes([77, 200])]),
}
for name, data in pngs.items():
    with open(os.path.join(corpus, "png", f"seed-{name}.png"), "wb") as f:
        f.write(data)
with open(os.path.join(here, "data", "tex.png"), "wb") as f:
    f.write(pngs["rgb8"])

objs = {
    "triangle": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "quad_uv_normals": "# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                       "vn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n",
    "negative_indices": "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -4 -3 -2\nf -1 -2 -3\n",
    "groups": "o a\ng g1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nf 1/1 2/2 3/1\ns 1\n",
}
for name, text in objs.items():
    with open(os.path.join(corpus, "obj", f"seed-{name}.obj"), "w") as f:
        f.write(text)
with open(os.path.join(here, "data", "mesh.obj"), "w") as f:
    f.write(objs["quad_uv_normals"])

def exr(width, height, channels):
    """Scanline OpenEXR, no compression. channels: list of (name, pixel_type, values per
    row as bytes-producer); pixel types 0 = UINT, 1 = HALF, 2 = FLOAT."""
    def attr(name, typ, data):
        return name.encode() + b"\0" + typ.encode() + b"\0" + struct.pack("<i", len(data)) + data
    chans = sorted(channels, key=lambda c: c[0])
    chlist = b"".join(c[0].encode() + b"\0" + struct.pack("<iB3xii", c[1], 0, 1, 1) for c in chans) + b"\0"
    box = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header = (attr("channels", "chlist", chlist) + attr("compression", "compression", b"\0")
              + attr("dataWindow", "box2i", box) + attr("displayWindow", "box2i", box)
              + attr("lineOrder", "lineOrder", b"\0") + attr("pixelAspectRatio", "float", struct.pack("<f", 1))
              + attr("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0))
              + attr("screenWindowWidth", "float", struct.pack("<f", 1)) + b"\0")
    head = struct.pack("<ii", 20000630, 2) + header
    blocks = []
    for y in range(height):
        data = b"".join(c[2](y) for c in chans)
        blocks.append(struct.pack("<ii", y, len(data)) + data)
    offset = len(head) + 8 * height
    table = b""
    for b in blocks:
        table += struct.pack("<Q", offset)
        offset += len(b)
    return head + table + b"".join(blocks)

exrs = {
    "rgb_float": exr(2, 2, [(c, 2, lambda y, c=c: struct.pack("<2f", 0.25 * y, 1.5 if c == "G" else 0.5))
                            for c in "RGB"]),
    "y_half": exr(2, 1, [("Y", 1, lambda y: struct.pack("<2e", 0.5, 2.0))]),
    "r_uint": exr(1, 2, [("R", 0, lambda y: struct.pack("<I", 7 + y))]),
}
for name, data in exrs.items():
    with open(os.path.join(corpus, "exr", f"seed-{name}.exr"), "wb") as f:
        f.write(data)
with open(os.path.join(here, "data", "tex.exr"), "wb") as f:
    f.write(exrs["rgb_float"])

# MERL tables for fuzz_merl (its header says how the bytes describe a table): byte 0 odd,
# a base value for every entry, then runs (u32 first entry, u16 run length - 1, double).
def merl_seed(base, runs=()):
    return b"\x01" + struct.pack("<d", base) + b"".join(struct.pack("<IHd", *r) for r in runs)

os.makedirs(os.path.join(corpus, "merl"), exist_ok=True)
merl_seeds = {
    "lambert": merl_seed(0.5 / 3.141592653589793 * 1500),           # red f = 0.5/pi everywhere
    "missing-blocks": merl_seed(150.0, [(0, 65535, -1.0), (1458000 + 300000, 65535, -1.0)]),
    "at-the-bound": merl_seed(1e30 * 1500, [(5, 0, 0.0)]),          # f = 1e30 1/sr in red
    "above-the-bound": merl_seed(150.0, [(3 * 180 + 4, 0, 1e42 * 1500)]),  # issue 39
    "overflow-1e300": merl_seed(150.0, [(2 * 1458000 + 7, 0, 1e300)]),
    "denormal-peak": merl_seed(5e-324, [(0, 200, 1e6)]),
    "negative-zero": merl_seed(-0.0, [(1000, 100, 1.0)]),
    "nan-entry": merl_seed(1.0, [(17, 0, float("nan"))]),
    "all-missing": merl_seed(-1.0),
}
for name, data in merl_seeds.items():
    with open(os.path.join(corpus, "merl", f"seed-{name}"), "wb") as f:
        f.write(data)
# Byte 0 even: a file's bytes as they are (header and size checks).
with open(os.path.join(corpus, "merl", "seed-file-header-only"), "wb") as f:
    f.write(b"\x00" + struct.pack("<3i", 90, 90, 180))
with open(os.path.join(corpus, "merl", "seed-file-wrong-header"), "wb") as f:
    f.write(b"\x00" + struct.pack("<3i", 90, 90, 360) + struct.pack("<d", 1.0))

# RGL .bsdf files for fuzz_rgl (its header says how the bytes describe a file): byte 0
# odd: float bytes over a small valid file; byte 0 even: a whole tensor_file.
os.makedirs(os.path.join(corpus, "rgl"), exist_ok=True)
def tensor_file(fields):
    head = b"tensor_file\x00" + bytes([1, 0]) + struct.pack("<I", len(fields))
    offset = len(head) + sum(2 + len(n) + 2 + 1 + 8 + 8 * len(shape) for n, _, shape, _ in fields)
    table, blobs = b"", b""
    for name, dtype, shape, data in fields:
        table += struct.pack("<H", len(name)) + name + struct.pack("<HBQ", len(shape), dtype, offset + len(blobs))
        table += b"".join(struct.pack("<Q", s) for s in shape)
        blobs += data
    return head + table + blobs
with open(os.path.join(corpus, "rgl", "seed-values-constant"), "wb") as f:
    f.write(b"\x01" + struct.pack("<f", 0.25) * 64)
with open(os.path.join(corpus, "rgl", "seed-file-two-fields"), "wb") as f:
    f.write(b"\x00" + tensor_file([(b"theta_i", 10, [2], struct.pack("<2f", 0, 1)), (b"jacobian", 1, [1], b"\x01")]))

# Surface descriptions for fuzz_surface (SPEC §3 `gonio measure --surface`).
surfaces = [
    '{"type":"flat","material":{"type":"diffuse"}}',
    '{"type":"gaussian","alpha":0.3,"resolution":16,"material":{"type":"mirror"}}',
    '{"type":"gaussian","alpha":[0.1,0.5],"resolution":32,"correlation":0.25,"seed":7,"size":2,'
    '"material":{"type":"roughconductor","alpha":0.1,"material":"Au"}}',
    '{"type":"vgroove","angle":45,"grooves":4,"material":{"type":"dielectric","eta":1.5}}',
    '{"type":"image","file":"tex.png","height":0.1,"material":{"type":"diffuse","reflectance":0.8}}',
]
os.makedirs(os.path.join(corpus, "surface"), exist_ok=True)
for i, s in enumerate(surfaces):
    with open(os.path.join(corpus, "surface", f"seed-{i:02d}"), "wb") as f:
        f.write(s.encode())

# MaterialX documents for fuzz_mtlx: the test documents (tests/data/mtlx and its errors/),
# one with a material's name before a NUL byte.
import glob, shutil
os.makedirs(os.path.join(corpus, "mtlx"), exist_ok=True)
mtlx_dir = os.path.join(here, "..", "tests", "data", "mtlx")
for path in sorted(glob.glob(os.path.join(mtlx_dir, "*.mtlx")) + glob.glob(os.path.join(mtlx_dir, "errors", "*.mtlx"))):
    name = os.path.basename(path)
    prefix = "error-" if os.path.basename(os.path.dirname(path)) == "errors" else ""
    shutil.copyfile(path, os.path.join(corpus, "mtlx", f"seed-{prefix}{name}"))
with open(os.path.join(mtlx_dir, "several.mtlx"), "rb") as f:
    several = f.read()
with open(os.path.join(corpus, "mtlx", "seed-named-M_blue"), "wb") as f:
    f.write(b"M_blue\0" + several)
