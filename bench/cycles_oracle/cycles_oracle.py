#!/usr/bin/python3
"""Blender's Cycles as an independent oracle for vscan's returned light: per-pixel radiance of the
same scenes, direct and with one bounce. Starts a vscand from the build, builds each scene through
the API, scans it with the returned light (320 x 240 pinhole, the emitter at the camera or, for the
sl-* scenes, at a structured-light sensor's projector beside it), converts each
point's measured electrons back to radiance (PixelGain and cos^4, as vscan computes them), renders the
same scene with Cycles on the CPU (bench/cycles_oracle/render_cycles.py), and compares pixel by pixel
away from silhouettes, fold lines and the cone's edge.

  VSCAN_BUILD_DIR=build/release VSCAN_SOURCE_DIR=. /usr/bin/python3 bench/cycles_oracle/cycles_oracle.py \\
      [--scenes camera|projector|NAME,...] [--samples 1024] [--indirect-samples 4096] [--json out.json] [--keep DIR]

Prints a Markdown table (docs/BENCHMARKS.md, "Cycles as an oracle for the returned light"). Without `blender` on PATH it
says so and exits 0 ("skipped"); --self-check checks the conversions without a server or Blender.
"""

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
BLENDER_SCRIPT = os.path.join(HERE, "render_cycles.py")

# The camera: 320 x 240, 60 degrees across, square pixels, principal point at the centre.
WIDTH, HEIGHT = 320, 240
FX = FY = (WIDTH / 2) / math.tan(math.radians(30))
CX, CY = WIDTH / 2, HEIGHT / 2
# The pixel: vscan's defaults but for the full well, raised so that nothing saturates, and an emitter
# strong enough for about 1e7..5e8 electrons: shot noise 0.005 % to 0.03 %.
EMITTER_W_PER_SR = 100.0
PIXEL = {"exposure_s": 0.01, "aperture_diameter_m": 0.004, "quantum_efficiency": 0.3, "wavelength_m": 850e-9}
FULL_WELL_E = 1e9
PLANCK_JS, LIGHT_MS = 6.62607015e-34, 299792458.0

LAMBERT_GREY = {"diffuse_albedo": 0.6, "metallic": 0.0, "roughness": 1.0, "specular_reflectance": 0.0}
LAMBERT_WHITE = {"diffuse_albedo": 0.9, "metallic": 0.0, "roughness": 1.0, "specular_reflectance": 0.0}
# The presets' values (server/engine/sensor/material.cpp), written out so that Blender gets the same.
BRUSHED_STEEL = {"diffuse_albedo": 0.58, "metallic": 1.0, "roughness": 0.35, "specular_reflectance": 0.04}
WHITE_ABS = {"diffuse_albedo": 0.85, "metallic": 0.0, "roughness": 0.45, "specular_reflectance": 0.045}


def pixel_gain():
    """vscan's CameraPixelGain: QE t A Omega lambda / (h c), A the pupil's area, Omega = 1 / (fx fy)."""
    area = math.pi * (PIXEL["aperture_diameter_m"] / 2) ** 2
    photon_j = PLANCK_JS * LIGHT_MS / PIXEL["wavelength_m"]
    return PIXEL["quantum_efficiency"] * PIXEL["exposure_s"] * area / (FX * FY) / photon_j


def pixel_cos4():
    """(HEIGHT, WIDTH): cos^4 of each pixel centre's ray to the optical axis (vscan's OffAxisFalloff)."""
    u = (np.arange(WIDTH) + 0.5 - CX) / FX
    v = (np.arange(HEIGHT) + 0.5 - CY) / FY
    uu, vv = np.meshgrid(u, v)
    cos2 = 1.0 / (1.0 + uu * uu + vv * vv)
    return cos2 * cos2


def rectangle(centre, axis_u, axis_v, half_u, half_v):
    """Two triangles: the rectangle centre +- half_u axis_u +- half_v axis_v."""
    c, u, v = (np.asarray(x, float) for x in (centre, axis_u, axis_v))
    vertices = [c - half_u * u - half_v * v, c + half_u * u - half_v * v, c + half_u * u + half_v * v,
                c - half_u * u + half_v * v]
    return np.array(vertices), np.array([[0, 1, 2], [0, 2, 3]])


def facing_rectangle(foot, half_u, half_v, emitter=(0.0, 0.0, 0.0)):
    """A rectangle about `foot` in the plane whose normal there bisects the directions to the camera
    (the origin) and to the emitter: the emitter's specular peak lies at `foot`."""
    foot = np.asarray(foot, float)
    to_emitter = np.asarray(emitter, float) - foot
    normal = -foot / np.linalg.norm(foot) + to_emitter / np.linalg.norm(to_emitter)
    normal /= np.linalg.norm(normal)
    u = np.cross((0.0, 1.0, 0.0), normal)
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    return rectangle(foot, u, v, half_u, half_v)


def box(centre, size, yaw_deg):
    """A closed cube of edge `size` about `centre`, turned yaw_deg about the vertical (y), 12 triangles."""
    yaw = math.radians(yaw_deg)
    turn = np.array([[math.cos(yaw), 0.0, math.sin(yaw)], [0.0, 1.0, 0.0], [-math.sin(yaw), 0.0, math.cos(yaw)]])
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]) * size
    vertices = corners @ turn.T + np.asarray(centre, float)
    # Corner index 4x + 2y + z; each face's two triangles wound outwards.
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    faces = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    return vertices, np.array(faces)


class Projector:
    """A structured-light sensor's projector beside the oracle's camera: the returned light's emitter sits
    at its offset and faces along its axis (vscan: sensor::SensorFromProjector)."""

    def __init__(self, offset, convergence_m, fov_deg):
        self.offset = np.asarray(offset, float)
        self.convergence_m = float(convergence_m)
        self.fov_deg = fov_deg  # (horizontal, vertical), wide enough to hold the emitter's cone

    def position(self):
        return self.offset

    def axis(self):
        """Parallel to the camera's, or towards (0, 0, convergence) on the camera's axis."""
        if self.convergence_m <= 0:
            return np.array([0.0, 0.0, 1.0])
        axis = np.array([0.0, 0.0, self.convergence_m]) - self.offset
        return axis / np.linalg.norm(axis)

    def sensor_spec(self, sensor_pb2, common_pb2):
        """SensorSpec.structured_light: the oracle's pinhole camera and this projector, no disparity step."""
        camera = sensor_pb2.PinholeCamera(width=WIDTH, height=HEIGHT, near=0.05, far=10.0,
                                          intrinsics=sensor_pb2.Intrinsics(fx=FX, fy=FY, cx=CX, cy=CY))
        x, y, z = (float(v) for v in self.offset)
        scanner = sensor_pb2.StructuredLightScanner(
            camera=camera, projector_offset=common_pb2.Vector3(x=x, y=y, z=z),
            projector_horizontal_fov_deg=self.fov_deg[0], projector_vertical_fov_deg=self.fov_deg[1],
            convergence_distance=self.convergence_m)
        return sensor_pb2.SensorSpec(structured_light=scanner)


AT_CAMERA = None  # a time-of-flight layout: the emitter at the camera, along its axis


def emitter_pose(projector):
    """(position, unit axis) of the emitter in the sensor frame."""
    if projector is None:
        return np.zeros(3), np.array([0.0, 0.0, 1.0])
    return projector.position(), projector.axis()


def scenes():
    """name -> (objects [(vertices, faces, material)], emitter half angle in degrees, description,
    projector: None for the emitter at the camera, else a Projector)."""
    tilt = math.radians(35)
    # (a) a Lambertian plane 1 m ahead turned 35 degrees about the vertical, in a 20-degree cone
    # whose edge crosses the image.
    plane_a = rectangle((0.0, 0.0, 1.0), (math.cos(tilt), 0.0, math.sin(tilt)), (0.0, 1.0, 0.0), 1.2, 0.9)
    # (b) brushed steel (left) and white ABS (right), each turned so that its specular peak lies in view.
    steel = facing_rectangle((-0.25, -0.05, 0.9), 0.21, 0.45)
    plastic = facing_rectangle((0.25, 0.08, 0.9), 0.21, 0.45)
    # (c) a right-angled corner of two white Lambertian walls, the fold 1 m ahead, each wall at 45 degrees.
    s2 = math.sqrt(0.5)
    corner = [rectangle((0.0, 0.0, 1.0) + 0.3 * np.array(a), a, (0.0, 1.0, 0.0), 0.3, 0.6)
              for a in ((s2, 0.0, -s2), (-s2, 0.0, -s2))]
    # (d) the same two planes with the right one Lambertian: the light the steel sends it is then checked
    # independently (the glossy weights of a bounce's first surface are the mapping's weak point).
    lambert_right = dict(WHITE_ABS, specular_reflectance=0.0)
    # Structured light: the projector 0.2 m to the camera's right (+x), its axis converging on the
    # camera's at the scene's depth. (e) a white wall 1.2 m ahead filling the image, a grey floor meeting
    # it 0.15 m below the camera and a white cube standing on the floor before the wall, which shadows
    # wall and floor on its left and lights both; the 30-degree cone, tilted 11 degrees towards -x,
    # crosses the image's right side and corners.
    box_projector = Projector((0.2, 0.0, 0.0), 1.0, (90.0, 90.0))
    wall = rectangle((0.0, 0.0, 1.2), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), 0.8, 0.6)
    floor = rectangle((0.0, 0.15, 0.85), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.8, 0.35)
    cube = box((-0.05, 0.05, 0.85), 0.2, 30.0)
    # (f) the brushed-steel and white-abs pair turned so that the projector's specular peaks are in view:
    # each normal bisects the directions to the camera and to the projector, so the highlights moved
    # with the projector.
    pair_projector = Projector((0.2, 0.0, 0.0), 0.9, (150.0, 150.0))
    sl_steel = facing_rectangle((-0.25, -0.05, 0.9), 0.21, 0.45, pair_projector.position())
    sl_plastic = facing_rectangle((0.25, 0.08, 0.9), 0.21, 0.45, pair_projector.position())
    return {
        "lambert-plane": ([(*plane_a, LAMBERT_GREY)], 20.0, "Lambertian plane (albedo 0.6) at 35 deg, 20 deg cone",
                          AT_CAMERA),
        "ggx-planes": ([(*steel, BRUSHED_STEEL), (*plastic, WHITE_ABS)], 60.0,
                       "brushed-steel and white-abs planes, specular peaks in view", AT_CAMERA),
        "steel-lambert": ([(*steel, BRUSHED_STEEL), (*plastic, lambert_right)], 60.0,
                          "brushed-steel plane beside a Lambertian one (albedo 0.85)", AT_CAMERA),
        "corner": ([(*w, LAMBERT_WHITE) for w in corner], 60.0, "right-angled corner of two white walls (albedo 0.9)",
                   AT_CAMERA),
        "sl-box-shadow": ([(*wall, LAMBERT_WHITE), (*floor, LAMBERT_GREY), (*cube, LAMBERT_WHITE)], 30.0,
                          "structured light: white cube on a grey floor before a white wall, its projector "
                          "shadow in view",
                          box_projector),
        "sl-ggx-planes": ([(*sl_steel, BRUSHED_STEEL), (*sl_plastic, WHITE_ABS)], 60.0,
                          "structured light: brushed-steel and white-abs planes, the projector's peaks in view",
                          pair_projector),
        "sl-steel-lambert": ([(*sl_steel, BRUSHED_STEEL), (*sl_plastic, lambert_right)], 60.0,
                             "structured light: brushed-steel plane beside a Lambertian one (albedo 0.85)",
                             pair_projector),
    }


# The scenes scanned with a structured-light sensor, whose emitter is its projector.
PROJECTOR_SCENES = "sl-box-shadow,sl-ggx-planes,sl-steel-lambert"
CAMERA_SCENES = "lambert-plane,ggx-planes,steel-lambert,corner"


def write_ply(path, vertices, faces):
    with open(path, "w") as f:
        f.write(f"ply\nformat ascii 1.0\nelement vertex {len(vertices)}\nproperty float x\nproperty float y\n"
                f"property float z\nelement face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for p in vertices:
            f.write(f"{p[0]:.9g} {p[1]:.9g} {p[2]:.9g}\n")
        for t in faces:
            f.write("3 " + " ".join(str(int(i)) for i in t) + "\n")


def vscan_radiance(client, scene_id, half_angle, indirect_samples, stride, seed, sensor=None):
    """(radiance image with NaN where no measured point, instance image, clean positions image, seconds).
    sensor: None for the oracle's pinhole camera (the emitter at the camera), else a SensorSpec (a
    structured-light scanner with the same camera; the emitter at its projector). The pixels the
    projector does not light (shadowed, outside its field) are rejected, so NaN here."""
    light = {"emitter_w_per_sr": EMITTER_W_PER_SR, "emitter_half_angle_deg": half_angle, "full_well_e": FULL_WELL_E,
             **PIXEL}
    if indirect_samples:
        light.update(indirect_samples=indirect_samples, indirect_stride_px=stride)
    start = time.monotonic()
    result = client.scan(scene_id, width=WIDTH, height=HEIGHT, intrinsics=(FX, FY, CX, CY), near=0.05, far=10.0,
                         sensor=sensor, pose_matrix=np.eye(4), frame="sensor", seed=seed,
                         fields=["intensity", "pixel", "instance", "clean"], returned_light=light)
    seconds = time.monotonic() - start
    radiance = np.full(HEIGHT * WIDTH, np.nan)
    instances = np.zeros(HEIGHT * WIDTH, np.int64)
    clean = np.full((HEIGHT * WIDTH, 3), np.nan)
    pixels = np.asarray(result.pixels, np.int64)
    # `intensity` is the measured electrons: gain x radiance x cos^4 plus shot and read noise.
    radiance[pixels] = np.asarray(result.intensities, float) / (pixel_gain() * pixel_cos4().ravel()[pixels])
    instances[pixels] = np.asarray(result.instance_ids, np.int64)
    clean[pixels] = np.asarray(result.clean_positions, float)
    return radiance.reshape(HEIGHT, WIDTH), instances.reshape(HEIGHT, WIDTH), clean.reshape(HEIGHT, WIDTH, 3), seconds


def blender_scene(objects, half_angle, projector, bounces, samples, seed):
    """The JSON render_cycles.py reads: the camera, the spot light at the emitter (the projector's
    position and axis, or the camera's), the meshes and the render settings."""
    position, axis = emitter_pose(projector)
    return {"width": WIDTH, "height": HEIGHT, "fx": FX, "fy": FY, "cx": CX, "cy": CY,
            "emitter": {"position": position.tolist(), "axis": axis.tolist(), "half_angle_deg": half_angle,
                        "w_per_sr": EMITTER_W_PER_SR},
            "objects": [{"vertices": v.tolist(), "faces": f.tolist(), "material": m} for v, f, m in objects],
            "samples": samples, "max_bounces": bounces, "seed": seed, "threads": os.cpu_count() or 2}


def cycles_radiance(blender, objects, half_angle, projector, bounces, samples, seed, workdir, tag):
    spec = blender_scene(objects, half_angle, projector, bounces, samples, seed)
    scene_json = os.path.join(workdir, f"{tag}.json")
    out = os.path.join(workdir, f"{tag}.npy")
    with open(scene_json, "w") as f:
        json.dump(spec, f)
    start = time.monotonic()
    run = subprocess.run([blender, "-b", "--factory-startup", "-P", BLENDER_SCRIPT, "--", scene_json, out],
                         capture_output=True, text=True, timeout=3600)
    seconds = time.monotonic() - start
    reported = [line for line in run.stdout.splitlines() if line.startswith("CYCLES_ORACLE ")]
    if run.returncode != 0 or not reported or not os.path.exists(out):
        raise RuntimeError(f"blender failed ({run.returncode}): {run.stdout[-2000:]} {run.stderr[-2000:]}")
    info = json.loads(reported[-1].split(" ", 1)[1])
    return np.load(out).astype(float), info, seconds


def erode(mask, radius):
    """Pixels whose whole (2 radius + 1)^2 neighbourhood lies in mask (outside the image counts as out)."""
    padded = np.pad(mask, radius, constant_values=False)
    out = np.ones_like(mask)
    for dy in range(-radius, radius + 1):
        for dx in range(-radius, radius + 1):
            out &= padded[radius + dy:radius + dy + mask.shape[0], radius + dx:radius + dx + mask.shape[1]]
    return out


def compared_pixels(radiance, instances, clean, half_angle, projector=None, margin_px=2, cone_margin_deg=1.0):
    """Measured pixels whose neighbourhood (margin_px) is measured on the same object and that lie more
    than cone_margin_deg inside the emitter's cone (about the projector's axis from its position, or the
    camera's): no silhouette, fold, projector shadow's edge (the shadowed pixels are not measured) or
    cone edge in reach."""
    measured = np.isfinite(radiance)
    same = measured.copy()
    for dy in range(-margin_px, margin_px + 1):
        for dx in range(-margin_px, margin_px + 1):
            shifted = np.roll(np.roll(instances, dy, axis=0), dx, axis=1)
            same &= shifted == instances
    with np.errstate(invalid="ignore"):
        position, axis = emitter_pose(projector)
        from_emitter = clean - position
        cosine = from_emitter @ axis / np.linalg.norm(from_emitter, axis=2)
        angle = np.degrees(np.arccos(np.clip(cosine, -1, 1)))
        inside = angle < half_angle - cone_margin_deg
    return erode(measured & same, margin_px) & inside


def agreement(vscan, cycles, mask, tolerance):
    rel = np.abs(vscan[mask] - cycles[mask]) / np.maximum(np.abs(cycles[mask]), 1e-30)
    signed = (vscan[mask] - cycles[mask]) / np.maximum(np.abs(cycles[mask]), 1e-30)
    return {"pixels": int(mask.sum()), "median_rel": float(np.median(rel)), "p95_rel": float(np.percentile(rel, 95)),
            "within_tol": float(np.mean(rel <= tolerance)), "mean_signed": float(np.mean(signed)),
            "max_rel": float(np.max(rel))}


def unlit_terms(vscan, cycles):
    """Direct light: the pixels vscan returns no point for (no surface, or one its emitter does not
    light: the projector's shadow, outside its cone), and how many of them Cycles lights, and how many
    pixels Cycles leaves dark that vscan measured: both 0 where the shadows and the cone agree."""
    missing, dark = ~np.isfinite(vscan), ~(cycles > 0)
    return {"unmeasured": int(missing.sum()), "unmeasured_lit_in_cycles": int((missing & ~dark).sum()),
            "measured_dark_in_cycles": int((~missing & dark).sum())}


def indirect_terms(vscan, cycles, vscan_direct, cycles_direct, mask, instances):
    """The one-bounce light alone (each renderer's one-bounce image less its direct one): its share of
    the signal, and vscan's sum over Cycles' sum on the compared pixels (a bias the per-pixel noise of
    both Monte Carlo estimates does not hide), over all compared pixels and per object (in the order
    the scene lists them)."""
    vscan_ind, cycles_ind = vscan - vscan_direct, cycles - cycles_direct
    if not np.any(cycles_ind[mask] > 0):
        return {"indirect_share": 0.0, "indirect_ratio": None}
    by_object = []
    for instance in np.unique(instances[mask]):
        chosen = mask & (instances == instance)
        by_object.append(float(np.sum(vscan_ind[chosen]) / np.sum(cycles_ind[chosen])))
    return {"indirect_share": float(np.mean(cycles_ind[mask] / cycles[mask])),
            "indirect_ratio": float(np.sum(vscan_ind[mask]) / np.sum(cycles_ind[mask])),
            "indirect_ratio_by_object": by_object}


def self_check():
    """The conversions without a server or Blender: the gain of vscan's default pixel for this camera,
    the falloff on the axis and at a corner, and each scene's meshes well formed."""
    gain = pixel_gain()
    area = math.pi * 0.002 ** 2
    expected = 0.3 * 0.01 * area / (FX * FY) * 850e-9 / (PLANCK_JS * LIGHT_MS)
    assert abs(gain / expected - 1) < 1e-12, (gain, expected)
    cos4 = pixel_cos4()
    corner = math.cos(math.atan(math.hypot((0.5 - CX) / FX, (0.5 - CY) / FY))) ** 4
    assert abs(cos4[0, 0] - corner) < 1e-12 and cos4.max() < 1 and cos4.max() > 0.9999
    for name, (objects, half_angle, _, projector) in scenes().items():
        assert 0 < half_angle < 90, name
        for vertices, faces, material in objects:
            assert vertices.shape[1] == 3 and faces.max() < len(vertices), name
            assert set(material) == {"diffuse_albedo", "metallic", "roughness", "specular_reflectance"}, name
        assert (projector is not None) == (name in PROJECTOR_SCENES.split(",")), name
        if projector is not None:
            # The projector's field holds the emitter's whole cone: the cone alone bounds the lit area.
            assert half_angle < min(projector.fov_deg) / 2, name
    self_check_projector()
    # Two objects side by side: only pixels 3 or more from the image's edge, the other object and the
    # cone's edge (8 degrees off the axis here) are compared.
    radiance = np.ones((HEIGHT, WIDTH))
    instances = np.where(np.arange(WIDTH)[None, :] < 100, 1, 2) * np.ones((HEIGHT, 1), np.int64)
    u = (np.arange(WIDTH) + 0.5 - CX) / FX
    v = (np.arange(HEIGHT) + 0.5 - CY) / FY
    clean = np.stack(np.broadcast_arrays(u[None, :], v[:, None], np.ones((HEIGHT, 1))), axis=2)
    mask = compared_pixels(radiance, instances, clean, 9.0)
    angle = np.degrees(np.arctan(np.hypot(u[None, :], v[:, None])))
    columns = np.arange(WIDTH)[None, :]
    assert not np.any(mask & ((np.abs(columns - 99.5) < 2.5) | (angle > 8.0))) and np.any(mask), "mask"
    assert np.all(mask[(angle < 7.9) & (np.abs(columns - 99.5) > 3)]), "mask keeps the inside"
    unlit = unlit_terms(np.array([np.nan, np.nan, 1.0, 2.0]), np.array([0.0, 1.0, 0.0, 2.0]))
    assert unlit == {"unmeasured": 2, "unmeasured_lit_in_cycles": 1, "measured_dark_in_cycles": 1}, unlit
    stats = agreement(np.array([1.0, 1.02, 0.9]), np.ones(3), np.ones(3, bool), 0.05)
    assert abs(stats["median_rel"] - 0.02) < 1e-12 and abs(stats["within_tol"] - 2 / 3) < 1e-12, stats
    # The Blender side imports bpy, which only Blender has: compile it without running it.
    with open(BLENDER_SCRIPT) as f:
        compile(f.read(), BLENDER_SCRIPT, "exec")
    print(f"self-check passed: gain {gain:.6g} e per W/(m^2 sr), cos^4 at the corner {cos4[0, 0]:.6f}")


class _Messages:
    """Stand-in for the generated sensor_pb2 and common_pb2 (the self-check runs without a build):
    each message is the dict of the fields it was given."""

    def __getattr__(self, name):
        return lambda **fields: dict(fields, message=name)


def self_check_projector():
    """The structured-light mapping: the emitter at the projector with its axis (SensorFromProjector),
    the scanner's fields, the cone mask about that axis, the shadow's edge and the scenes' geometry."""
    projector = Projector((0.2, 0.0, 0.0), 1.0, (90.0, 80.0))
    axis = projector.axis()
    assert np.allclose(axis, np.array([-0.2, 0.0, 1.0]) / math.hypot(0.2, 1.0)), axis
    assert np.allclose(Projector((0.2, 0.0, 0.0), 0.0, (90.0, 90.0)).axis(), (0, 0, 1))
    position, pose_axis = emitter_pose(None)
    assert np.allclose(position, 0) and np.allclose(pose_axis, (0, 0, 1))
    spec = blender_scene([], 30.0, projector, 1, 16, 7)
    assert spec["emitter"]["position"] == [0.2, 0.0, 0.0] and np.allclose(spec["emitter"]["axis"], axis), spec
    assert spec["emitter"]["half_angle_deg"] == 30.0 and spec["emitter"]["w_per_sr"] == EMITTER_W_PER_SR
    scanner = projector.sensor_spec(_Messages(), _Messages())["structured_light"]
    camera = scanner["camera"]
    assert (camera["width"], camera["height"]) == (WIDTH, HEIGHT) and camera["intrinsics"]["fx"] == FX, camera
    assert scanner["projector_offset"] == {"x": 0.2, "y": 0.0, "z": 0.0, "message": "Vector3"}, scanner
    assert (scanner["projector_horizontal_fov_deg"], scanner["projector_vertical_fov_deg"]) == (90.0, 80.0)
    assert scanner["convergence_distance"] == 1.0 and "disparity_step_px" not in scanner
    # A wall 1 m ahead lit from the projector in a 20-degree cone about its tilted axis: the mask
    # follows that cone, not one about the camera's axis, and keeps 2 px away from a shadow (a hole of
    # pixels the projector does not light, NaN as vscan leaves them).
    u = (np.arange(WIDTH) + 0.5 - CX) / FX
    v = (np.arange(HEIGHT) + 0.5 - CY) / FY
    clean = np.stack(np.broadcast_arrays(u[None, :], v[:, None], np.ones((HEIGHT, 1))), axis=2)
    radiance = np.ones((HEIGHT, WIDTH))
    radiance[100:140, 60:80] = np.nan
    mask = compared_pixels(radiance, np.ones((HEIGHT, WIDTH), np.int64), clean, 20.0, projector)
    off_axis = clean - projector.offset
    angle = np.degrees(np.arccos(off_axis @ axis / np.linalg.norm(off_axis, axis=2)))
    clear_of_hole = erode(np.isfinite(radiance), 3)
    assert not np.any(mask & (angle > 19.0)) and np.all(mask[(angle < 18.9) & clear_of_hole]), "cone about projector"
    assert not np.any(mask[98:142, 58:82]) and np.all(mask[100:140, 83][angle[100:140, 83] < 18.9]), "shadow edge"
    assert mask[:, :WIDTH // 2].sum() > mask[:, WIDTH // 2:].sum(), "the cone leans towards -x"
    # The cube: closed (each edge in two triangles, opposite ways) and wound outwards.
    vertices, faces = box((-0.05, 0.05, 0.85), 0.2, 30.0)
    edges = {(int(a), int(b)) for t in faces for a, b in zip(t, np.roll(t, -1))}
    assert len(edges) == 36 and all((b, a) in edges for a, b in edges), "cube closed"
    for t in faces:
        p0, p1, p2 = vertices[t]
        assert np.dot(np.cross(p1 - p0, p2 - p0), (p0 + p1 + p2) / 3 - vertices.mean(axis=0)) > 0, "cube outwards"
    # The plane's normal bisects the ways to the camera and to the projector: the mirror direction of
    # the projector's light at the foot goes to the camera.
    foot = np.array([-0.25, -0.05, 0.9])
    plane, _ = facing_rectangle(foot, 0.21, 0.45, projector.offset)
    normal = np.cross(plane[1] - plane[0], plane[2] - plane[0])
    normal /= np.linalg.norm(normal)
    incoming = (foot - projector.offset) / np.linalg.norm(foot - projector.offset)
    mirrored = incoming - 2 * np.dot(incoming, normal) * normal
    assert np.allclose(mirrored, -foot / np.linalg.norm(foot)), (mirrored, foot)


def share(row):
    return f"{100 * row['indirect_share']:.2f} %" if "indirect_share" in row else "-"


def ratio(row):
    if row.get("indirect_ratio") is None:
        return "-"
    objects = row.get("indirect_ratio_by_object", [])
    each = " (" + ", ".join(f"{r:.3f}" for r in objects) + ")" if len(objects) > 1 else ""
    return f"{row['indirect_ratio']:.4f}{each}"


def floor(row):
    value = row.get("cycles_vs_cycles_median_rel")
    return f"{100 * value:.3f} %" if value is not None else "-"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=1024, help="Cycles samples per pixel for the one-bounce renders")
    parser.add_argument("--direct-samples", type=int, default=16, help="Cycles samples per pixel, direct only")
    parser.add_argument("--indirect-samples", type=int, default=4096, help="vscan's indirect_samples")
    parser.add_argument("--stride", type=int, default=2, help="vscan's indirect_stride_px")
    parser.add_argument("--tolerance", type=float, default=0.01, help="relative error counted as agreement")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--scenes", default=CAMERA_SCENES + "," + PROJECTOR_SCENES,
                        help="comma-separated scene names; 'camera' and 'projector' stand for each group")
    parser.add_argument("--json")
    parser.add_argument("--keep", help="directory to keep the scene files and both images in")
    parser.add_argument("--principal-point", help="cx,cy in pixels instead of the image's centre")
    parser.add_argument("--self-check", action="store_true", help="check the conversions and exit")
    args = parser.parse_args()
    if args.principal_point:
        global CX, CY
        CX, CY = (float(x) for x in args.principal_point.split(","))
    if args.self_check:
        self_check()
        return 0
    blender = shutil.which("blender")
    if blender is None:
        print("skipped: `blender` is not on PATH (Debian: apt-get install --no-install-recommends blender); "
              "vscan itself does not need it")
        return 0
    os.environ.setdefault("VSCAN_SOURCE_DIR", ROOT)
    os.environ.setdefault("VSCAN_BUILD_DIR", os.path.join(ROOT, "build", "release"))
    sys.path.insert(0, os.path.join(ROOT, "tests", "integration"))
    sys.path.insert(0, os.path.join(ROOT, "client", "python"))
    from harness import Server  # noqa: E402
    from vscan import Client  # noqa: E402

    workdir = args.keep or tempfile.mkdtemp(prefix="vscan-cycles-")
    os.makedirs(workdir, exist_ok=True)
    server = Server().start()
    client = Client(server.address)
    rows, version = [], None
    try:
        groups = {"camera": CAMERA_SCENES, "projector": PROJECTOR_SCENES}
        names = ",".join(groups.get(n, n) for n in args.scenes.split(",")).split(",")
        for name in names:
            objects, half_angle, description, projector = scenes()[name]
            sensor = None
            if projector is not None:
                from vscan.v1 import common_pb2, sensor_pb2  # noqa: E402
                sensor = projector.sensor_spec(sensor_pb2, common_pb2)
            scene_id = client.create_scene("cycles-" + name).scene_id
            for i, (vertices, faces, material) in enumerate(objects):
                path = os.path.join(workdir, f"{name}-{i}.ply")
                write_ply(path, vertices, faces)
                mesh = client.upload_mesh(path, "m", material=material).mesh_id
                client.add_object(scene_id, mesh)
            direct = None
            for light, bounces in (("direct", 0), ("one bounce", 1)):
                samples = args.indirect_samples if bounces else 0
                radiance, instances, clean, vscan_s = vscan_radiance(client, scene_id, half_angle, samples,
                                                                     args.stride, args.seed, sensor)
                spp = args.samples if bounces else args.direct_samples
                cycles, info, blender_s = cycles_radiance(blender, objects, half_angle, projector, bounces, spp,
                                                          args.seed, workdir, f"{name}-{bounces}")
                version = info["version"]
                if args.keep:
                    np.save(os.path.join(workdir, f"{name}-{bounces}-vscan.npy"), radiance)
                mask = compared_pixels(radiance, instances, clean, half_angle, projector) & (cycles > 0)
                row = {"scene": name, "description": description, "light": light, "cycles_spp": spp,
                       "emitter": "camera" if projector is None else "projector",
                       "vscan_indirect_samples": samples, "vscan_stride": args.stride if samples else None,
                       "vscan_s": vscan_s, "cycles_render_s": info["render_s"], "blender_s": blender_s,
                       **agreement(radiance, cycles, mask, args.tolerance)}
                if bounces == 0:
                    direct = (radiance, cycles)
                    row.update(unlit_terms(radiance, cycles))
                else:
                    row.update(indirect_terms(radiance, cycles, *direct, mask, instances))
                    if row["indirect_share"] > 1e-4:
                        # Cycles against itself at another seed: the per-pixel Monte Carlo noise floor.
                        again, _, _ = cycles_radiance(blender, objects, half_angle, projector, bounces, spp,
                                                      args.seed + 1, workdir, f"{name}-{bounces}-seed2")
                        row["cycles_vs_cycles_median_rel"] = agreement(again, cycles, mask, args.tolerance)["median_rel"]
                rows.append(row)
                print(json.dumps(row), file=sys.stderr, flush=True)
    finally:
        client.close()
        server.cleanup()
        if not args.keep:
            shutil.rmtree(workdir, ignore_errors=True)
    print(f"Blender {version}, Cycles CPU; {WIDTH} x {HEIGHT} pinhole, emitter {EMITTER_W_PER_SR} W/sr at the camera "
          f"(sl-*: at the structured-light projector); "
          f"tolerance {100 * args.tolerance:g} %")
    print("| Scene | Light | Pixels | Median rel. error | 95th pct | Within tol. | Mean signed | Indirect share "
          "| Indirect vscan / Cycles | Cycles vs Cycles | vscan s | Cycles s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['scene']} | {r['light']} | {r['pixels']} | {100 * r['median_rel']:.3f} % | "
              f"{100 * r['p95_rel']:.3f} % | {100 * r['within_tol']:.1f} % | {100 * r['mean_signed']:+.3f} % | "
              f"{share(r)} | {ratio(r)} | {floor(r)} | "
              f"{r['vscan_s']:.2f} | {r['cycles_render_s']:.1f} |")
    print("\n| Scene | Pixels without a vscan point | of them lit in Cycles | vscan's points dark in Cycles |")
    print("|---|---|---|---|")
    for r in rows:
        if "unmeasured" in r:
            print(f"| {r['scene']} | {r['unmeasured']} | {r['unmeasured_lit_in_cycles']} | "
                  f"{r['measured_dark_in_cycles']} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"rows": rows, "blender": version, "tolerance": args.tolerance}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
