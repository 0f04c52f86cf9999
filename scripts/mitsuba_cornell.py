#!/usr/bin/env python3
"""Renders fixtures/scenes/cornell-box.ron with gridrt and the same scene with
Mitsuba 3 (variant scalar_rgb), then compares them and times both.

Not part of `cargo test`: it needs Mitsuba 3 from PyPI and a release build.

    python3 -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba numpy
    cargo build --release -p gridrt-io
    /tmp/mi/bin/python scripts/mitsuba_cornell.py --spp 256 --threads 2

The Mitsuba scene is built from the same OBJ: faces grouped by `usemtl`,
MTL `Kd` as diffuse reflectance (shortBox and tallBox overridden to
(0.725, 0.71, 0.68) as in the gridrt scene), `Ke` as the radiance of a
one-sided area emitter on the lamp (which, as in gridrt, reflects nothing),
camera at (0, 1, 3.9) looking at (0, 1, 0), vertical fov 40°, 256×256, box
filter, path tracer. It prints the mean colour of each image, the RMSE
between them, and as the noise floor the RMSE between two Mitsuba renders
with different seeds; and the wall-clock and CPU time of each renderer.

Mitsuba renders with its `independent` sampler (its default) and with its
`multijitter` sampler (the family of gridrt's default, correlated
multi-jittered sampling). With `--reference-spp N` it also renders a Mitsuba
reference at N spp and prints each image's RMSE against it and the time
each renderer would need for gridrt's error (time × (RMSE / gridrt's RMSE)²,
as variance falls as 1/spp): the speed at equal quality, not only at equal
samples.
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OBJ = os.path.join(ROOT, "fixtures/meshes/cornell_box/CornellBox-Original.obj")
MTL = os.path.join(ROOT, "fixtures/meshes/cornell_box/CornellBox-Original.mtl")
SCENE = os.path.join(ROOT, "fixtures/scenes/cornell-box.ron")
OVERRIDE = {"shortBox": (0.725, 0.71, 0.68), "tallBox": (0.725, 0.71, 0.68)}


def read_mtl(path):
    mats, cur = {}, None
    for line in open(path):
        w = line.split("#")[0].split()
        if not w:
            continue
        if w[0] == "newmtl":
            cur = w[1]
            mats[cur] = {"Kd": (0.0, 0.0, 0.0), "Ke": (0.0, 0.0, 0.0)}
        elif w[0] in ("Kd", "Ke") and cur:
            mats[cur][w[0]] = tuple(float(x) for x in w[1:4])
    return mats


def read_obj(path):
    """Vertices and triangles (fans of the polygons) grouped by material."""
    verts, groups, mat = [], {}, None
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            verts.append([float(x) for x in w[1:4]])
        elif w[0] == "usemtl":
            mat = w[1]
        elif w[0] == "f":
            idx = []
            for t in w[1:]:
                i = int(t.split("/")[0])
                idx.append(i - 1 if i > 0 else len(verts) + i)
            for k in range(1, len(idx) - 1):
                groups.setdefault(mat, []).append((idx[0], idx[k], idx[k + 1]))
    return np.array(verts, dtype=np.float64), groups


def mitsuba_scene(mi, spp, seed, sampler):
    mats = read_mtl(MTL)
    verts, groups = read_obj(OBJ)
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 65},
        "sensor": {
            "type": "perspective",
            "fov": 40.0,
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[0, 1, 3.9], target=[0, 1, 0], up=[0, 1, 0]
            ),
            "sampler": {"type": sampler, "sample_count": spp, "seed": seed},
            "film": {
                "type": "hdrfilm",
                "width": 256,
                "height": 256,
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
            },
        },
    }
    folder = tempfile.mkdtemp(prefix="cornell-mi-")
    for name, tris in groups.items():
        # One OBJ of triangles per material, in the file's winding.
        path = os.path.join(folder, f"{name}.obj")
        with open(path, "w") as f:
            for t in tris:
                for i in t:
                    f.write("v %r %r %r\n" % tuple(float(x) for x in verts[i]))
            for k in range(len(tris)):
                f.write(f"f {3 * k + 1} {3 * k + 2} {3 * k + 3}\n")
        m = mats.get(name, {"Kd": (0.8, 0.8, 0.8), "Ke": (0, 0, 0)})
        kd = OVERRIDE.get(name, m["Kd"])
        shape = {"type": "obj", "filename": path, "face_normals": True}
        if max(m["Ke"]) > 0:
            # gridrt's emissive material reflects nothing.
            kd = (0.0, 0.0, 0.0)
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": m["Ke"]}}
        shape["bsdf"] = {"type": "diffuse", "reflectance": {"type": "rgb", "value": kd}}
        d[name] = shape
    return mi.load_dict(d)


def render_mitsuba(mi, dr, spp, threads, seed, sampler="independent"):
    dr.set_thread_count(threads)
    scene = mitsuba_scene(mi, spp, seed, sampler)
    t0, c0 = time.perf_counter(), time.process_time()
    img = mi.render(scene, spp=spp, seed=seed)
    arr = np.array(img, dtype=np.float64)[:, :, :3]
    return arr, (time.perf_counter() - t0, time.process_time() - c0)


def render_gridrt(binary, spp, threads, out):
    stats = out + ".json"
    cmd = [binary, "render", SCENE, "-o", out, "--spp", str(spp), "--threads", str(threads),
           "--stats", stats, "-q"]
    t0 = time.perf_counter()
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, check=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall = time.perf_counter() - t0
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    s = json.load(open(stats))
    return (wall, cpu), s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--gridrt", default=os.path.join(ROOT, "target/release/gridrt"))
    ap.add_argument("--keep", help="folder for the images (default: a temporary one)")
    ap.add_argument("--reference-spp", type=int, default=0,
                    help="also render a Mitsuba reference at this many spp and compare errors")
    a = ap.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    folder = a.keep or tempfile.mkdtemp(prefix="cornell-")
    os.makedirs(folder, exist_ok=True)
    ours_path = os.path.join(folder, "gridrt.exr")

    wall, stats = render_gridrt(a.gridrt, a.spp, a.threads, ours_path)
    ours = np.array(mi.Bitmap(ours_path), dtype=np.float64)[:, :, :3]
    mi1, t1 = render_mitsuba(mi, dr, a.spp, a.threads, seed=1)
    mi2, _ = render_mitsuba(mi, dr, a.spp, a.threads, seed=2)
    mj, tj = render_mitsuba(mi, dr, a.spp, a.threads, seed=3, sampler="multijitter")
    mi.Bitmap(mi1.astype(np.float32)).write(os.path.join(folder, "mitsuba.exr"))

    def rmse(x, y):
        return float(np.sqrt(np.mean((x - y) ** 2)))

    def blocks(x, k=16):
        h, w, c = x.shape
        return x.reshape(h // k, k, w // k, k, c).mean(axis=(1, 3))

    print(f"images in {folder}")
    print(f"spp {a.spp}, threads {a.threads}")
    print("mean colour  gridrt  " + " ".join(f"{v:.5f}" for v in ours.mean(axis=(0, 1))))
    print("mean colour  mitsuba " + " ".join(f"{v:.5f}" for v in mi1.mean(axis=(0, 1))))
    print("mean colour  mitsuba " + " ".join(f"{v:.5f}" for v in mi2.mean(axis=(0, 1))) + "  (second seed)")
    rel = (ours.mean(axis=(0, 1)) - mi1.mean(axis=(0, 1))) / mi1.mean(axis=(0, 1))
    print("mean relative difference gridrt - mitsuba: " + " ".join(f"{v:+.4f}" for v in rel))
    print(f"per-pixel RMSE gridrt vs mitsuba   {rmse(ours, mi1):.5f}")
    print(f"per-pixel RMSE mitsuba vs mitsuba  {rmse(mi2, mi1):.5f}  (noise floor, two seeds)")
    print(f"16x16-block RMSE gridrt vs mitsuba  {rmse(blocks(ours), blocks(mi1)):.5f}")
    print(f"16x16-block RMSE mitsuba vs mitsuba {rmse(blocks(mi2), blocks(mi1)):.5f}")
    # On a shared machine wall time depends on the other load; CPU time
    # (all threads) is the steadier measure of work.
    print(f"time gridrt  {wall[0]:.3f} s wall, {wall[1]:.3f} s CPU (whole process; render {stats['render_time']:.3f} s wall)")
    print(f"time mitsuba {t1[0]:.3f} s wall, {t1[1]:.3f} s CPU (mi.render only, independent)")
    print(f"time mitsuba {tj[0]:.3f} s wall, {tj[1]:.3f} s CPU (mi.render only, multijitter)")
    print(f"CPU time ratio mitsuba / gridrt: {t1[1] / wall[1]:.3f} (independent), "
          f"{tj[1] / wall[1]:.3f} (multijitter)")
    if a.reference_spp:
        ref, tr = render_mitsuba(mi, dr, a.reference_spp, a.threads, seed=4)
        print(f"reference: Mitsuba, independent, {a.reference_spp} spp ({tr[1]:.1f} s CPU)")
        e0 = rmse(ours, ref)
        for name, img, cpu in [("gridrt", ours, wall[1]), ("mitsuba independent", mi1, t1[1]),
                               ("mitsuba multijitter", mj, tj[1])]:
            e = rmse(img, ref)
            print(f"RMSE vs reference {name:20s} {e:.5f}; CPU time for gridrt's error "
                  f"{cpu * (e / e0) ** 2:.3f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
