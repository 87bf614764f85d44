#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpora: small files from ../shared/data and configs/, the
handmade seeds in fuzz/seeds/, and small PNGs and PCDs generated here (a whole image of the
targets' 16x12 camera, a whole cloud of their 8x6 one). Usage: make_seeds.py OUT_DIR SHARED_DATA_DIR
(OUT_DIR/<target>/ per target; SHARED_DATA_DIR may be missing: a clone alone gets the rest)."""
import glob
import os
import shutil
import struct
import sys
import zlib

HEAD = 4096  # bytes of a large shared file kept as a seed (its header; the rest reads as truncated)


def png(width, height, bit_depth, colour_type, row_bytes, interlace=0):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    raw = b"".join(b"\x00" + row_bytes(v) for v in range(height))
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, interlace)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def pcd(data_kind, fields, width=8, height=6):
    names, sizes, types = zip(*fields)
    header = ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS %s\nSIZE %s\nTYPE %s\nCOUNT %s\n"
              "WIDTH %d\nHEIGHT %d\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA %s\n" % (
                  " ".join(names), " ".join(map(str, sizes)), " ".join(types), " ".join("1" for _ in names),
                  width, height, width * height, data_kind))
    points = []
    for v in range(height):
        for u in range(width):
            z = 1.0 + 0.01 * u if (u + v) % 7 else float("nan")
            value = {"x": (u - 3.5) * z / 5, "y": (v - 2.5) * z / 5, "z": z, "rgb": 0x336699, "rgba": 0xff336699,
                     "label": (u // 4) + 1, "intensity": 0.5}
            points.append([value[n] for n in names])
    pack = {("F", 4): "f", ("U", 4): "I", ("U", 1): "B"}
    if data_kind == "ascii":
        body = "".join(" ".join(("nan" if p != p else "%g" % p) if t == "F" else str(int(p)) for p, t in zip(point, types)) + "\n"
                       for point in points).encode()
    elif data_kind == "binary":
        body = b"".join(struct.pack("<" + "".join(pack[(t, s)] for _, s, t in fields), *point) for point in points)
    else:  # binary_compressed: fields one after another, LZF of literal runs only (a valid LZF stream)
        raw = b"".join(struct.pack("<" + pack[(t, s)] * len(points), *[p[k] for p in points]) for k, (_, s, t) in enumerate(fields))
        lzf = b"".join(bytes([len(raw[i:i + 32]) - 1]) + raw[i:i + 32] for i in range(0, len(raw), 32))
        body = struct.pack("<II", len(lzf), len(raw)) + lzf
    return header.encode() + body


def main(out, shared):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    def put(target, name, data):
        os.makedirs(os.path.join(out, target), exist_ok=True)
        with open(os.path.join(out, target, name), "wb") as f:
            f.write(data)
    def copy(target, path, prefix=""):
        with open(path, "rb") as f:
            put(target, prefix + os.path.basename(path), f.read(HEAD if target in ("pcd", "depth_png", "color_png") else 1 << 20))
    # Handmade seeds.
    for target_dir in glob.glob(os.path.join(root, "fuzz", "seeds", "*")):
        for path in glob.glob(os.path.join(target_dir, "*")):
            copy(os.path.basename(target_dir), path)
    # configs/.
    for path in glob.glob(os.path.join(root, "configs", "cameras", "*.yaml")):
        copy("camera_yaml", path)
    copy("config_yaml", os.path.join(root, "configs", "default.yaml"))
    for path in glob.glob(os.path.join(root, "configs", "scenes", "*.yaml")):
        copy("scene_yaml", path)
    for path in glob.glob(os.path.join(root, "configs", "studies", "*.yaml")):
        copy("study_yaml", path)
    for path in glob.glob(os.path.join(root, "configs", "rooms", "*.yaml")):
        copy("rooms_yaml", path)
    # Generated images and clouds.
    put("depth_png", "gray16.png", png(16, 12, 16, 0, lambda v: b"".join(struct.pack(">H", 5000 + 100 * u + v) for u in range(16))))
    put("depth_png", "gray16_interlaced.png", png(16, 12, 16, 0, lambda v: struct.pack(">H", 7000) * 16, interlace=1))
    put("depth_png", "gray8.png", png(16, 12, 8, 0, lambda v: bytes(range(16))))
    put("color_png", "rgb8.png", png(16, 12, 8, 2, lambda v: bytes((u * 16, v * 20, 128) [k] for u in range(16) for k in range(3))))
    put("color_png", "rgba8.png", png(16, 12, 8, 6, lambda v: bytes([40, 80, 120, 255] * 16)))
    put("color_png", "gray8.png", png(16, 12, 8, 0, lambda v: bytes(range(0, 256, 16))))
    put("color_png", "rgb16.png", png(16, 12, 16, 2, lambda v: b"\x12\x34" * 48))
    xyz = [("x", 4, "F"), ("y", 4, "F"), ("z", 4, "F")]
    for kind in ("ascii", "binary", "binary_compressed"):
        put("pcd", "xyzrgb_%s.pcd" % kind, pcd(kind, xyz + [("rgb", 4, "F" if kind == "ascii" else "U")]))
        put("pcd", "osd_%s.pcd" % kind, pcd(kind, [("label", 4, "U")] + xyz + [("rgba", 4, "U")]))
    put("pcd", "xyz_ascii.pcd", pcd("ascii", xyz))
    # ../shared/data: lists, trajectories, the heads of images and clouds.
    if os.path.isdir(shared):
        for seq in sorted(glob.glob(os.path.join(shared, "*", ""))):
            name = os.path.basename(os.path.dirname(seq)) + "_"
            for kind, target in (("rgb.txt", "file_list"), ("depth.txt", "file_list"), ("associations.txt", "file_list"),
                                 ("groundtruth.txt", "trajectory"), ("groundtruth_icl_raw.txt", "trajectory")):
                if os.path.isfile(seq + kind):
                    with open(seq + kind, "rb") as f:
                        put(target, name + kind, b"".join(f.readlines()[:40]))
            for kind, target in (("depth", "depth_png"), ("rgb", "color_png")):
                images = sorted(glob.glob(os.path.join(seq, kind, "*.png")))
                if images:
                    copy(target, images[0], name)
        for path in sorted(glob.glob(os.path.join(shared, "osd_boxes_learn", "pcd", "*.pcd")))[:2]:
            copy("pcd", path, "osd_")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
