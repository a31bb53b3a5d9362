#!/usr/bin/env python3
"""Reads back every run-time asset folder under the folders given, as AI2-THOR's loaders do.

The asset hook (ai2thor's ProceduralAssetHookRunner, objathor's asset_conversion/util.py) looks
for `<dir>/<uid>/<uid>.<ext>` trying `.json`, `.json.gz`, `.msgpack`, `.msgpack.gz`, `.pkl.gz`
in that order, loads the dict, rewrites its texture paths to files of the asset folder (by
file name) and sends it to Unity's CreateRuntimeAsset with the annotations of
`thor_metadata.json`. This check does the same reading and checks what Unity then relies on:
the dict's fields and their types, one normal and one uv per vertex, triangle indices in
range, convex colliders with their own triangles, the textures present and real JPEG files,
the metadata's properties. It prints one line per asset and `N passed, N failed` last; the
exit code is the number of failures (at most 100).
"""
import gzip
import json
import os
import struct
import sys

EXTENSIONS = [".json", ".json.gz", ".msgpack", ".msgpack.gz", ".pkl.gz"]
PRIMARY = {"Static", "CanPickup", "Moveable"}
SECONDARY = {"Receptacle", "CanBreak", "CanOpen", "CanToggleOnOff"}


def load(folder, uid):
    for ext in EXTENSIONS:
        path = os.path.join(folder, uid + ext)
        if os.path.isfile(path):
            if ext == ".json":
                with open(path, "r", encoding="utf-8") as f:
                    return ext, json.load(f)
            if ext == ".json.gz":
                with gzip.open(path, "rt", encoding="utf-8") as f:
                    return ext, json.load(f)
            raise ValueError(f"{ext} files are not written by holoc")
    raise FileNotFoundError(f"no {uid}.<ext> in {folder}")


def point(p, axes):
    return isinstance(p, dict) and all(isinstance(p.get(a), (int, float)) for a in axes)


def jpeg_size(path):
    """Width and height of a baseline or progressive JPEG, from its SOF marker."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:2] != b"\xff\xd8":
        raise ValueError(f"{os.path.basename(path)} is not a JPEG file")
    i = 2
    while i + 4 <= len(data):
        if data[i] != 0xFF:
            raise ValueError("bad JPEG marker")
        marker = data[i + 1]
        length = struct.unpack(">H", data[i + 2 : i + 4])[0]
        if marker in (0xC0, 0xC1, 0xC2):
            h, w = struct.unpack(">HH", data[i + 5 : i + 9])
            return w, h
        i += 2 + length
    raise ValueError("no frame header in the JPEG file")


def check(folder, uid):
    ext, asset = load(folder, uid)
    assert ext == ".json", ext
    assert asset["name"] == uid, "name is not the folder's uid"
    verts = asset["vertices"]
    assert verts and all(point(v, "xyz") for v in verts), "vertices"
    n = len(verts)
    assert len(asset["normals"]) == n and all(point(v, "xyz") for v in asset["normals"]), "normals"
    assert len(asset["uvs"]) == n and all(point(v, "xy") for v in asset["uvs"]), "uvs"
    tris = asset["triangles"]
    assert tris and len(tris) % 3 == 0, "triangles"
    assert all(isinstance(t, int) and 0 <= t < n for t in tris), "triangle index out of range"
    for v in asset["normals"]:
        length = (v["x"] ** 2 + v["y"] ** 2 + v["z"] ** 2) ** 0.5
        assert abs(length - 1) < 1e-3, "normal not of unit length"
    assert all(0 <= uv["x"] <= 1 and 0 <= uv["y"] <= 1 for uv in asset["uvs"]), "uv outside 0..1"
    colliders = asset["colliders"]
    assert colliders, "no collider"
    for c in colliders:
        cv = c["vertices"]
        ct = c["triangles"]
        assert len(cv) >= 4 and all(point(v, "xyz") for v in cv), "collider vertices"
        assert len(ct) % 3 == 0 and all(0 <= t < len(cv) for t in ct), "collider triangles"
    assert isinstance(asset["receptacleCandidate"], bool)
    assert isinstance(asset["yRotOffset"], (int, float))
    assert all(point(v, "xyz") for v in asset["visibilityPoints"])
    phys = asset["physicalProperties"]
    for key in ("mass", "drag", "angularDrag"):
        assert isinstance(phys[key], (int, float)) and phys[key] >= 0, key
    assert isinstance(phys["useGravity"], bool) and isinstance(phys["isKinematic"], bool)
    # The hook's path rewrite: each texture is looked for in the asset folder by file name.
    for key in ("albedoTexturePath", "normalTexturePath"):
        path = os.path.join(folder, os.path.basename(asset[key]))
        w, h = jpeg_size(path)
        assert w > 0 and h > 0
    if asset.get("emissionTexturePath"):
        jpeg_size(os.path.join(folder, os.path.basename(asset["emissionTexturePath"])))
    with open(os.path.join(folder, "thor_metadata.json"), encoding="utf-8") as f:
        meta = json.load(f)["assetMetadata"]
    assert meta["primaryProperty"] in PRIMARY, meta["primaryProperty"]
    assert set(meta["secondaryProperties"]) <= SECONDARY, meta["secondaryProperties"]
    size = sum(os.path.getsize(os.path.join(folder, f)) for f in os.listdir(folder))
    return n, len(tris) // 3, size


def main():
    passed = failed = 0
    for root in sys.argv[1:]:
        for uid in sorted(os.listdir(root)):
            folder = os.path.join(root, uid)
            if not os.path.isdir(folder) or uid.startswith("."):
                continue
            try:
                n, t, size = check(folder, uid)
                print(f"ok {uid}: {n} vertices, {t} triangles, {size} bytes")
                passed += 1
            except Exception as e:  # noqa: BLE001 - every failure is reported
                print(f"FAILED {uid}: {type(e).__name__}: {e}")
                failed += 1
    print(f"{passed} passed, {failed} failed")
    sys.exit(min(failed, 100))


if __name__ == "__main__":
    main()
