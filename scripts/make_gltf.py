#!/usr/bin/env python3
"""Writes the project's own small glTF 2.0 files (docs/gltf.md): no file is fetched.

  make_gltf.py spheres -o F.gltf   five spheres, one per material feature (metal, rough
                                   dielectric, clearcoat, sheen, transmission), a floor,
                                   a spot and a directional light, a perspective camera
  make_gltf.py furnace -o F.gltf   one white sphere, no light (use as a "gltf" shape in a
                                   scene JSON with a uniform environment: a white
                                   non-absorbing sphere vanishes)
  make_gltf.py big N -o F.glb      an indexed grid of about N triangles with normals,
                                   texcoords and tangents (--no-tangents: without), for the
                                   load benchmark (bench/gltf_load.sh)

Buffers are data URIs in .gltf files and the binary chunk in .glb files.
"""
import argparse
import base64
import json
import math
import struct
import sys

import numpy as np


class Doc:
    def __init__(self):
        self.j = {"asset": {"version": "2.0", "generator": "gonio scripts/make_gltf.py"},
                  "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [],
                  "accessors": [], "bufferViews": [], "materials": []}
        self.bin = bytearray()

    def accessor(self, arr, type_, component=5126, minmax=False):
        arr = np.ascontiguousarray(arr)
        while len(self.bin) % 4:
            self.bin.append(0)
        off = len(self.bin)
        self.bin += arr.tobytes()
        self.j["bufferViews"].append({"buffer": 0, "byteOffset": off, "byteLength": arr.nbytes})
        a = {"bufferView": len(self.j["bufferViews"]) - 1, "componentType": component,
             "count": int(arr.shape[0]), "type": type_}
        if minmax:
            a["min"] = arr.min(axis=0).tolist()
            a["max"] = arr.max(axis=0).tolist()
        self.j["accessors"].append(a)
        return len(self.j["accessors"]) - 1

    def mesh(self, pos, nrm, uv, idx, material, tangents=None):
        attrs = {"POSITION": self.accessor(pos.astype(np.float32), "VEC3", minmax=True),
                 "NORMAL": self.accessor(nrm.astype(np.float32), "VEC3"),
                 "TEXCOORD_0": self.accessor(uv.astype(np.float32), "VEC2")}
        if tangents is not None:
            attrs["TANGENT"] = self.accessor(tangents.astype(np.float32), "VEC4")
        prim = {"attributes": attrs, "indices": self.accessor(idx.astype(np.uint32).reshape(-1), "SCALAR", 5125)}
        if material is not None:
            prim["material"] = material
        self.j["meshes"].append({"primitives": [prim]})
        return len(self.j["meshes"]) - 1

    def node(self, root=True, **kw):
        self.j["nodes"].append(kw)
        n = len(self.j["nodes"]) - 1
        if root:
            self.j["scenes"][0]["nodes"].append(n)
        return n

    def material(self, **kw):
        self.j["materials"].append(kw)
        return len(self.j["materials"]) - 1

    def write(self, path):
        binary = path.lower().endswith(".glb")
        j = dict(self.j)
        while len(self.bin) % 4:
            self.bin.append(0)
        j["buffers"] = [{"byteLength": len(self.bin)}]
        if not binary:
            j["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bytes(self.bin)).decode()
            with open(path, "w") as f:
                json.dump(j, f)
            return
        text = json.dumps(j).encode()
        text += b" " * ((4 - len(text) % 4) % 4)
        total = 12 + 8 + len(text) + 8 + len(self.bin)
        with open(path, "wb") as f:
            f.write(struct.pack("<4sII", b"glTF", 2, total))
            f.write(struct.pack("<I4s", len(text), b"JSON") + text)
            f.write(struct.pack("<I4s", len(self.bin), b"BIN\0") + bytes(self.bin))


def uv_sphere(n_lat, n_lon, r=1.0):
    th = np.linspace(0, math.pi, n_lat + 1)
    ph = np.linspace(0, 2 * math.pi, n_lon + 1)
    T, P = np.meshgrid(th, ph, indexing="ij")
    nrm = np.stack([np.sin(T) * np.sin(P), np.cos(T), np.sin(T) * np.cos(P)], -1).reshape(-1, 3)
    uv = np.stack([P / (2 * math.pi), T / math.pi], -1).reshape(-1, 2)
    idx = []
    for i in range(n_lat):
        for k in range(n_lon):
            a, b = i * (n_lon + 1) + k, (i + 1) * (n_lon + 1) + k
            idx += [a, b, a + 1, a + 1, b, b + 1]
    return nrm * r, nrm, uv, np.array(idx)


def grid(n, size=1.0):
    """(n+1)² vertices in the xz plane, 2n² triangles facing +y."""
    s = np.linspace(-size, size, n + 1, dtype=np.float32)
    X, Z = np.meshgrid(s, s, indexing="ij")
    pos = np.stack([X, np.zeros_like(X), Z], -1).reshape(-1, 3)
    nrm = np.tile(np.array([0, 1, 0], np.float32), (pos.shape[0], 1))
    uv = np.stack([(X + size) / (2 * size), (Z + size) / (2 * size)], -1).reshape(-1, 2)
    i = np.arange(n)
    a = (i[:, None] * (n + 1) + i[None, :]).reshape(-1)
    b = a + n + 1
    idx = np.stack([a, a + 1, b, a + 1, b + 1, b], -1).reshape(-1)
    return pos, nrm, uv, idx


def spheres(path):
    d = Doc()
    mats = [
        {"pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.64, 0.54, 1], "metallicFactor": 1, "roughnessFactor": 0.3}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 0.5}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1], "metallicFactor": 0, "roughnessFactor": 0.6},
         "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.05}}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.1, 0.1, 1], "metallicFactor": 0, "roughnessFactor": 0.8},
         "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.5, 0.9], "sheenRoughnessFactor": 0.4}}},
        {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 0.05},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.5}}},
    ]
    pos, nrm, uv, idx = uv_sphere(24, 48, 0.45)
    for i, m in enumerate(mats):
        mi = d.material(name=f"m{i}", **m)
        d.node(mesh=d.mesh(pos, nrm, uv, idx, mi), translation=[(i - 2) * 1.1, 0.45, 0])
    fm = d.material(name="floor", pbrMetallicRoughness={"baseColorFactor": [0.7, 0.7, 0.7, 1], "metallicFactor": 0, "roughnessFactor": 0.9})
    fp, fn, fu, fi = grid(4, 4.0)
    d.node(mesh=d.mesh(fp, fn, fu, fi, fm))
    d.j["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_clearcoat", "KHR_materials_sheen",
                             "KHR_materials_transmission", "KHR_materials_ior"]
    d.j["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "spot", "intensity": 60, "color": [1, 0.95, 0.9], "spot": {"innerConeAngle": 0.4, "outerConeAngle": 0.7}},
        {"type": "directional", "intensity": 1.5, "color": [0.8, 0.85, 1.0]}]}}
    s = math.sin(-math.pi / 4)
    d.node(translation=[0, 4, 1], rotation=[s, 0, 0, math.cos(math.pi / 4)], extensions={"KHR_lights_punctual": {"light": 0}})
    q = [math.sin(-0.5), 0.2, 0, math.cos(0.5)]
    n = math.sqrt(sum(x * x for x in q))
    d.node(rotation=[x / n for x in q], extensions={"KHR_lights_punctual": {"light": 1}})
    d.j["cameras"] = [{"name": "front", "type": "perspective", "perspective": {"yfov": 0.6, "aspectRatio": 16 / 9, "znear": 0.1}}]
    a = -0.25
    d.node(camera=0, translation=[0, 2.0, 6.5], rotation=[math.sin(a / 2), 0, 0, math.cos(a / 2)])
    d.write(path)


def furnace(path):
    d = Doc()
    m = d.material(name="white", pbrMetallicRoughness={"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 1},
                   extensions={"KHR_materials_specular": {"specularFactor": 0}})
    pos, nrm, uv, idx = uv_sphere(32, 64, 1.0)
    d.node(mesh=d.mesh(pos, nrm, uv, idx, m))
    d.j["extensionsUsed"] = ["KHR_materials_specular"]
    d.write(path)


def big(n_tris, path, tangents=True):
    n = max(1, int(math.sqrt(n_tris / 2)))
    pos, nrm, uv, idx = grid(n, 10.0)
    tan = np.tile(np.array([1, 0, 0, 1], np.float32), (pos.shape[0], 1)) if tangents else None
    d = Doc()
    m = d.material(name="grey", pbrMetallicRoughness={"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 0.5})
    d.node(mesh=d.mesh(pos, nrm, uv, idx, m, tan))
    d.write(path)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("kind", choices=["spheres", "furnace", "big"])
    p.add_argument("count", nargs="?", type=int, default=1000000)
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--no-tangents", action="store_true")
    a = p.parse_args()
    if a.kind == "spheres":
        spheres(a.output)
    elif a.kind == "furnace":
        furnace(a.output)
    else:
        big(a.count, a.output, not a.no_tangents)
    return 0


if __name__ == "__main__":
    sys.exit(main())
