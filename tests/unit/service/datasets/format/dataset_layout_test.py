"""Reads a written dataset without vscan's code: its own PNG decoder (zlib and the PNG filters),
json, numpy and a PLY header parse, and checks the files against each other and the geometry of
the synthetic bin (a floor 0.8 m below a camera looking straight down, two boxes on it), and the
same bin seen from three sampled views a scene (within 35 degrees of straight down, 0.7-0.9 m away)."""

import json
import os
import struct
import subprocess
import tempfile
import unittest
import zlib

import numpy as np

FIXTURE = os.environ.get("VSCAN_DATASET_FIXTURE", "")
# BOP's split folder for synthetic training images ("train" + "_" + split type "pbr").
SPLIT = "train_pbr"
CAMERA_HEIGHT_MM = 800.0
# Half a depth unit of quantisation plus float rounding of the back-projection.
SURFACE_TOLERANCE_MM = 0.2


def read_png(path):
    """8-bit or 16-bit greyscale, non-interlaced PNG as a 2-D numpy array and its bit depth."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    at, idat, header = 8, b"", None
    while at < len(data):
        (length,) = struct.unpack(">I", data[at:at + 4])
        kind, body = data[at + 4:at + 8], data[at + 8:at + 8 + length]
        at += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    width, height, depth, colour, _, _, interlace = header
    assert colour == 0 and interlace == 0 and depth in (8, 16), (path, header)
    bpp = depth // 8
    stride = width * bpp
    raw = zlib.decompress(idat)
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            left = line[i - bpp] if i >= bpp else 0
            up = previous[i]
            up_left = previous[i - bpp] if i >= bpp else 0
            if kind == 1:
                line[i] = (line[i] + left) & 0xFF
            elif kind == 2:
                line[i] = (line[i] + up) & 0xFF
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 0xFF
            elif kind == 4:
                p = left + up - up_left
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - up_left)
                pred = left if pa <= pb and pa <= pc else (up if pb <= pc else up_left)
                line[i] = (line[i] + pred) & 0xFF
        rows.append(bytes(line))
        previous = line
    dtype = ">u2" if depth == 16 else "u1"
    return np.frombuffer(b"".join(rows), dtype=dtype).reshape(height, width).astype(np.int64), depth


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    assert "format binary_little_endian 1.0" in header
    count = int(next(line for line in header if line.startswith("element vertex")).split()[2])
    kinds = {"float": "<f4", "uint": "<u4", "int": "<i4", "uchar": "u1", "double": "<f8"}
    fields = [(line.split()[2], kinds[line.split()[1]]) for line in header if line.startswith("property")]
    return np.frombuffer(data[end:], dtype=np.dtype(fields), count=count)


def read_ply_mesh(path):
    """Vertices of a binary PLY mesh whose vertices are float x, y, z and faces uchar/int lists."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    assert "format binary_little_endian 1.0" in header
    vertices = int(next(line for line in header if line.startswith("element vertex")).split()[2])
    faces = int(next(line for line in header if line.startswith("element face")).split()[2])
    assert "property list uchar int vertex_indices" in header
    xyz = np.frombuffer(data[end:], dtype="<f4", count=3 * vertices).reshape(vertices, 3)
    face = np.frombuffer(data[end + 12 * vertices:], dtype=np.dtype([("n", "u1"), ("i", "<i4", 3)]), count=faces)
    assert np.all(face["n"] == 3) and np.all(face["i"] < vertices) and np.all(face["i"] >= 0)
    assert len(data) == end + 12 * vertices + 13 * faces
    return xyz.astype(np.float64)


def load(path):
    with open(path) as f:
        return json.load(f)


class DatasetLayoutTest(unittest.TestCase):
    FIXTURE_ARGS = []
    VIEWS = 1

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.root = cls.tmp.name
        subprocess.run([FIXTURE] + cls.FIXTURE_ARGS + [cls.root], check=True)
        cls.manifest = load(os.path.join(cls.root, "dataset.json"))
        cls.index = load(os.path.join(cls.root, "scenes.json"))
        cls.models = load(os.path.join(cls.root, "models", "models_info.json"))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def scene_dirs(self):
        for entry in self.index["scenes"]:
            yield entry, os.path.join(self.root, SPLIT, "%06d" % entry["scene_id"])

    def images(self):
        """(scene directory, image name, camera, gt, info) of every image of every scene."""
        for _, scene in self.scene_dirs():
            cameras = load(os.path.join(scene, "scene_camera.json"))
            gts = load(os.path.join(scene, "scene_gt.json"))
            infos = load(os.path.join(scene, "scene_gt_info.json"))
            self.assertEqual(list(cameras), [str(i) for i in range(self.VIEWS)])
            self.assertEqual(list(gts), list(cameras))
            self.assertEqual(list(infos), list(cameras))
            for im_id in cameras:
                yield scene, "%06d" % int(im_id), cameras[im_id], gts[im_id], infos[im_id]

    def test_index_follows_the_plan_seed_then_bin_then_sensor(self):
        plan = self.manifest["plan"]
        self.assertEqual(self.manifest["layout_version"], 2)
        expected = [(s, b, c) for s in plan["seeds"] for b in plan["bins"] for c in plan["sensors"]]
        got = [(e["seed"], e["bin"], e["sensor"]) for e in self.index["scenes"]]
        self.assertEqual(got, expected)
        self.assertEqual([e["scene_id"] for e in self.index["scenes"]], list(range(len(expected))))
        self.assertEqual(sorted(os.listdir(os.path.join(self.root, SPLIT))),
                         ["%06d" % i for i in range(len(expected))])

    def test_manifest_names_views_only_when_the_plan_sets_them(self):
        if self.VIEWS == 1:
            self.assertNotIn("views", self.manifest["plan"])
        else:
            self.assertEqual(self.manifest["plan"]["views"], {"count": 3, "cone_deg": 35, "distance_m": [0.7, 0.9]})

    def test_records_match_the_files_on_disk(self):
        for entry, scene in self.scene_dirs():
            with open(os.path.join(scene, "scene_files.json"), "rb") as f:
                record_bytes = f.read()
            self.assertEqual(zlib.crc32(record_bytes), entry["record_crc32"])
            record = json.loads(record_bytes)
            self.assertEqual((record["seed"], record["bin"], record["sensor"]),
                             (entry["seed"], entry["bin"], entry["sensor"]))
            on_disk = sorted(os.path.relpath(os.path.join(d, n), scene)
                             for d, _, names in os.walk(scene) for n in names if n != "scene_files.json")
            self.assertEqual([f["path"] for f in record["files"]], on_disk)
            for listed in record["files"]:
                with open(os.path.join(scene, listed["path"]), "rb") as f:
                    data = f.read()
                self.assertEqual(len(data), listed["bytes"], listed["path"])
                self.assertEqual(zlib.crc32(data), listed["crc32"], listed["path"])

    def test_camera_pose_and_its_inverse_agree(self):
        for _, _, camera, _, _ in self.images():
            world_from_camera = np.array(camera["world_from_camera"]).reshape(4, 4)
            r_w2c = np.array(camera["cam_R_w2c"]).reshape(3, 3)
            t_w2c = np.array(camera["cam_t_w2c"])
            np.testing.assert_allclose(r_w2c @ world_from_camera[:3, :3], np.eye(3), atol=1e-12)
            np.testing.assert_allclose(r_w2c @ (world_from_camera[:3, 3] * 1000.0) + t_w2c, 0, atol=1e-9)

    def test_every_view_looks_at_the_floor_centre_from_within_the_plan(self):
        tilts = []
        for _, _, camera, _, _ in self.images():
            world_from_camera = np.array(camera["world_from_camera"]).reshape(4, 4)
            position, axes = world_from_camera[:3, 3] * 1000.0, world_from_camera[:3, :3]
            distance = np.linalg.norm(position)
            np.testing.assert_allclose(axes[:, 2], -position / distance, atol=1e-9)
            # Image x is the bin's x projected onto the image plane.
            self.assertAlmostEqual(float(axes[:, 0] @ np.cross([1.0, 0.0, 0.0], axes[:, 2])), 0.0, places=12)
            self.assertGreater(axes[0, 0], 0.0)
            tilts.append(np.degrees(np.arccos(-axes[2, 2])))
            if self.VIEWS == 1:
                self.assertAlmostEqual(distance, CAMERA_HEIGHT_MM)
                np.testing.assert_array_equal(axes, np.diag([1.0, -1.0, -1.0]))
            else:
                self.assertTrue(700.0 <= distance <= 900.0, distance)
        self.assertLessEqual(max(tilts), 35.0 + 1e-9)
        if self.VIEWS > 1:
            self.assertGreater(max(tilts), 15.0, "views should spread over the cone")

    def test_one_camera_file_per_sensor_matches_its_scenes(self):
        for entry, scene in self.scene_dirs():
            camera = load(os.path.join(self.root, "camera_%s.json" % entry["sensor"]))
            for view in load(os.path.join(scene, "scene_camera.json")).values():
                k = np.array(view["cam_K"]).reshape(3, 3)
                self.assertEqual([camera["fx"], camera["fy"], camera["cx"], camera["cy"]],
                                 [k[0, 0], k[1, 1], k[0, 2], k[1, 2]])
        self.assertFalse(os.path.exists(os.path.join(self.root, "camera.json")))

    def test_floor_pixels_back_project_onto_the_floor(self):
        for scene, image, camera, _, _ in self.images():
            depth, bits = read_png(os.path.join(scene, "depth", image + ".png"))
            instances, _ = read_png(os.path.join(scene, "instances", image + ".png"))
            self.assertEqual(bits, 16)
            self.assertEqual(depth.shape, (camera["height"], camera["width"]))
            floor = (instances == 0) & (depth > 0)
            self.assertGreater(floor.sum(), 100)
            if self.VIEWS == 1:
                np.testing.assert_allclose(depth[floor] * camera["depth_scale"], CAMERA_HEIGHT_MM, atol=1e-9)
            k = np.array(camera["cam_K"]).reshape(3, 3)
            ys, xs = np.nonzero(floor)
            z = depth[ys, xs] * camera["depth_scale"]
            in_camera = np.stack([(xs - k[0, 2]) / k[0, 0] * z, (ys - k[1, 2]) / k[1, 1] * z, z], axis=1)
            world_from_camera = np.array(camera["world_from_camera"]).reshape(4, 4)
            in_world = in_camera @ world_from_camera[:3, :3].T + world_from_camera[:3, 3] * 1000.0
            np.testing.assert_allclose(in_world[:, 2], 0.0, atol=SURFACE_TOLERANCE_MM)
            self.assertGreater((depth == 0).sum(), 0)

    def test_masks_boxes_and_counts_agree_with_the_instance_image(self):
        occluded = 0
        for scene, image, _, gt, info in self.images():
            depth, _ = read_png(os.path.join(scene, "depth", image + ".png"))
            instances, _ = read_png(os.path.join(scene, "instances", image + ".png"))
            self.assertEqual(len(gt), len(info))
            self.assertEqual(instances.max(), len(gt))
            for i, entry in enumerate(info):
                mask, bits = read_png(os.path.join(scene, "mask_visib", image + "_%06d.png" % i))
                self.assertEqual(bits, 8)
                self.assertTrue(np.array_equal(mask == 255, instances == i + 1))
                self.assertTrue(set(np.unique(mask)) <= {0, 255})
                ys, xs = np.nonzero(mask)
                self.assertEqual(entry["px_count_visib"], len(xs))
                self.assertEqual(entry["px_count_valid"], int(((mask == 255) & (depth > 0)).sum()))
                # BOP's calc_2d_bbox: width and height are max - min, not the pixel count across.
                box = [xs.min(), ys.min(), xs.max() - xs.min(), ys.max() - ys.min()]
                self.assertEqual(entry["bbox_visib"], box)
                self.assertGreaterEqual(entry["px_count_all"], entry["px_count_visib"])
                self.assertAlmostEqual(entry["visib_fract"], entry["px_count_visib"] / entry["px_count_all"])
                full, _ = read_png(os.path.join(scene, "mask", image + "_%06d.png" % i))
                self.assertTrue(set(np.unique(full)) <= {0, 255})
                self.assertTrue(np.all(full[mask == 255] == 255), "the visible part lies in the full silhouette")
                self.assertEqual(int((full == 255).sum()), entry["px_count_all"])
                fys, fxs = np.nonzero(full)
                self.assertEqual(entry["bbox_obj"], [fxs.min(), fys.min(), fxs.max() - fxs.min(), fys.max() - fys.min()])
                bx, by, bw, bh = entry["bbox_obj"]
                self.assertTrue(bx <= box[0] and by <= box[1])
                self.assertTrue(bx + bw >= box[0] + box[2] and by + bh >= box[1] + box[3])
                self.assertTrue(0 < entry["visib_fract"] <= 1)
                occluded += entry["visib_fract"] < 1
        self.assertGreater(occluded, 0, "the taller box should hide part of the other in some scene")

    def test_every_masked_pixel_back_projects_onto_its_part(self):
        for scene, image, camera, gt, _ in self.images():
            k = np.array(camera["cam_K"]).reshape(3, 3)
            depth, _ = read_png(os.path.join(scene, "depth", image + ".png"))
            instances, _ = read_png(os.path.join(scene, "instances", image + ".png"))
            for i, pose in enumerate(gt):
                model = self.models[str(pose["obj_id"])]
                lo = np.array([model["min_x"], model["min_y"], model["min_z"]])
                hi = lo + np.array([model["size_x"], model["size_y"], model["size_z"]])
                ys, xs = np.nonzero(instances == i + 1)
                z = depth[ys, xs] * camera["depth_scale"]
                in_camera = np.stack([(xs - k[0, 2]) / k[0, 0] * z, (ys - k[1, 2]) / k[1, 1] * z, z], axis=1)
                r = np.array(pose["cam_R_m2c"]).reshape(3, 3)
                t = np.array(pose["cam_t_m2c"])
                in_model = (in_camera - t) @ r
                self.assertTrue(np.all(in_model >= lo - SURFACE_TOLERANCE_MM), scene)
                self.assertTrue(np.all(in_model <= hi + SURFACE_TOLERANCE_MM), scene)
                # On a face: some coordinate sits at a bound of the box.
                on_face = ((np.abs(in_model - lo) <= SURFACE_TOLERANCE_MM) |
                           (np.abs(in_model - hi) <= SURFACE_TOLERANCE_MM))
                self.assertTrue(np.all(on_face.any(axis=1)), scene)

    def test_cloud_holds_one_point_per_measured_pixel_with_its_instance(self):
        for scene, image, camera, gt, info in self.images():
            depth, _ = read_png(os.path.join(scene, "depth", image + ".png"))
            cloud = read_ply(os.path.join(scene, "cloud", image + ".ply"))
            self.assertEqual(set(cloud.dtype.names), {"x", "y", "z", "nx", "ny", "nz", "instance"})
            self.assertEqual(len(cloud), int((depth > 0).sum()))
            for pose, entry in zip(gt, info):
                self.assertEqual(int((cloud["instance"] == pose["instance_id"]).sum()), entry["px_count_visib"])

    def test_scene_fill_says_which_bins_took_fewer_parts_than_planned(self):
        underfilled = []
        for entry, scene in self.scene_dirs():
            fill = load(os.path.join(scene, "scene_fill.json"))
            self.assertEqual(fill["underfilled"], fill["parts_placed"] < fill["parts_planned"])
            for view in load(os.path.join(scene, "scene_gt.json")).values():
                self.assertEqual(fill["parts_placed"], len(view))
            if fill["underfilled"]:
                underfilled.append((entry["seed"], entry["bin"]))
        # The synthetic plan's seed 12 far-pair asks for a part more than it holds, for both sensors.
        self.assertEqual(underfilled, [(12, "far-pair"), (12, "far-pair")])

    def test_scene_materials_name_every_placed_part_the_same_for_a_fills_sensors(self):
        chosen = {}
        for entry, scene in self.scene_dirs():
            materials = load(os.path.join(scene, "scene_materials.json"))["instances"]
            for view in load(os.path.join(scene, "scene_gt.json")).values():
                self.assertEqual(sorted(m["obj_id"] for m in materials), sorted(p["obj_id"] for p in view))
            for m in materials:
                self.assertIn(m["material"]["preset"],
                              {"machined-aluminium", "black-anodised-aluminium", "white-abs"})
                # A part type has one material in a scene; both sensors of a fill see the same.
                key = (entry["seed"], entry["bin"], m["obj_id"])
                self.assertEqual(chosen.setdefault(key, m["material"]["preset"]), m["material"]["preset"], key)

    def test_model_meshes_in_millimetres_beside_models_info(self):
        for obj_id, info in self.models.items():
            ply = read_ply_mesh(os.path.join(self.root, "models", "obj_%06d.ply" % int(obj_id)))
            lo, hi = ply.min(axis=0), ply.max(axis=0)
            np.testing.assert_allclose(lo, [info["min_x"], info["min_y"], info["min_z"]], atol=1e-3)
            np.testing.assert_allclose(hi - lo, [info["size_x"], info["size_y"], info["size_z"]], atol=1e-3)

    def test_models_info_in_millimetres_with_symmetries(self):
        self.assertEqual(sorted(self.models), ["1", "2"])
        self.assertAlmostEqual(self.models["1"]["diameter"], 2 * (80**2 + 50**2 + 30**2) ** 0.5, places=3)
        self.assertAlmostEqual(self.models["2"]["size_z"], 140.0, places=3)
        self.assertEqual(len(self.models["1"]["symmetries_discrete"]), 1)
        self.assertEqual(len(self.models["2"]["symmetries_discrete"]), 3)
        quarter = np.array(self.models["2"]["symmetries_discrete"][0]).reshape(4, 4)
        np.testing.assert_allclose(quarter[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-12)


class MultiViewDatasetLayoutTest(DatasetLayoutTest):
    FIXTURE_ARGS = ["--views"]
    VIEWS = 3

    def test_views_of_a_scene_differ_and_share_their_parts(self):
        for _, scene in self.scene_dirs():
            cameras = load(os.path.join(scene, "scene_camera.json"))
            poses = [np.array(c["world_from_camera"]) for c in cameras.values()]
            self.assertFalse(any(np.array_equal(poses[0], p) for p in poses[1:]), scene)
            gts = list(load(os.path.join(scene, "scene_gt.json")).values())
            for view, camera in zip(gts, cameras.values()):
                world_from_camera = np.array(camera["world_from_camera"]).reshape(4, 4)
                # The same part in the world seen from every view: world_from_model agrees.
                for pose, first in zip(view, gts[0]):
                    self.assertEqual(pose["instance_id"], first["instance_id"])
                    world = world_from_camera[:3, :3] @ np.array(pose["cam_t_m2c"]) + world_from_camera[:3, 3] * 1000
                    world0 = (np.array(list(cameras.values())[0]["world_from_camera"]).reshape(4, 4))
                    expected = world0[:3, :3] @ np.array(first["cam_t_m2c"]) + world0[:3, 3] * 1000
                    np.testing.assert_allclose(world, expected, atol=1e-6)


class ShardedDatasetTest(unittest.TestCase):
    FIXTURE_ARGS = []

    def test_two_shard_processes_and_a_merge_write_what_one_process_writes(self):
        with tempfile.TemporaryDirectory() as one, tempfile.TemporaryDirectory() as sharded:
            subprocess.run([FIXTURE] + self.FIXTURE_ARGS + [one], check=True)
            for index in ("1", "0"):
                subprocess.run([FIXTURE] + self.FIXTURE_ARGS + [sharded, index, "2"], check=True)
            subprocess.run([FIXTURE] + self.FIXTURE_ARGS + [sharded, "merge"], check=True)

            def tree(root):
                files = {}
                for d, _, names in os.walk(root):
                    for n in names:
                        with open(os.path.join(d, n), "rb") as f:
                            files[os.path.relpath(os.path.join(d, n), root)] = f.read()
                return files

            expected, actual = tree(one), tree(sharded)
            self.assertEqual(sorted(expected), sorted(actual))
            for path in expected:
                self.assertEqual(expected[path], actual[path], path)


class ShardedMultiViewDatasetTest(ShardedDatasetTest):
    FIXTURE_ARGS = ["--views"]


if __name__ == "__main__":
    unittest.main()
