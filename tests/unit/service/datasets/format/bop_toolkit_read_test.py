"""Reads a written dataset with the BOP benchmark's own loaders (bop_toolkit_lib's inout and
dataset_params), so that "BOP layout" means what the benchmark's code reads, not what vscan believes.

The toolkit is found at $VSCAN_BOP_TOOLKIT, else at shared/tools/bop_toolkit in a folder above the
repository; without it the test is skipped and says so. Debian 12 lacks python3-png and Debian's
imageio has no imageio.v2; where those (or scipy) are not installed, stand-ins are put in their
place: imageio.v2.imread decodes PNG with the layout test's own decoder, png and scipy.spatial's
distance only satisfy the toolkit's module-level imports (no loader used here calls them)."""

import os
import subprocess
import sys
import tempfile
import types
import unittest

import numpy as np

import dataset_layout_test as layout

HERE = os.path.dirname(os.path.abspath(__file__))


def find_toolkit():
    given = os.environ.get("VSCAN_BOP_TOOLKIT")
    if given:
        return given if os.path.isdir(os.path.join(given, "bop_toolkit_lib")) else None
    folder = HERE
    while os.path.dirname(folder) != folder:
        folder = os.path.dirname(folder)
        candidate = os.path.join(folder, "shared", "tools", "bop_toolkit")
        if os.path.isdir(os.path.join(candidate, "bop_toolkit_lib")):
            return candidate
    return None


def stand_in_missing_modules():
    """Returns the names of the modules replaced by stand-ins."""
    replaced = []
    try:
        import imageio
        if "imageio.v2" not in sys.modules:
            sys.modules["imageio.v2"] = getattr(imageio, "v2", imageio)
    except ImportError:
        imageio = types.ModuleType("imageio")
        v2 = types.ModuleType("imageio.v2")
        v2.imread = lambda path: layout.read_png(str(path))[0]
        imageio.v2 = v2
        sys.modules["imageio"], sys.modules["imageio.v2"] = imageio, v2
        replaced.append("imageio")
    try:
        import png  # noqa: F401
    except ImportError:
        sys.modules["png"] = types.ModuleType("png")
        replaced.append("png")
    try:
        import scipy.spatial.distance  # noqa: F401
    except ImportError:
        scipy = types.ModuleType("scipy")
        spatial = types.ModuleType("scipy.spatial")
        distance = types.ModuleType("scipy.spatial.distance")
        scipy.spatial, spatial.distance = spatial, distance
        sys.modules.update({"scipy": scipy, "scipy.spatial": spatial, "scipy.spatial.distance": distance})
        replaced.append("scipy")
    return replaced


TOOLKIT = find_toolkit()


@unittest.skipIf(TOOLKIT is None, "bop_toolkit not found: set VSCAN_BOP_TOOLKIT to a checkout holding "
                 "bop_toolkit_lib/ (github.com/thodan/bop_toolkit) to read the dataset with BOP's loaders")
class BopToolkitReadsTheDatasetTest(unittest.TestCase):
    FIXTURE_ARGS = []
    VIEWS = 1

    @classmethod
    def setUpClass(cls):
        cls.stand_ins = stand_in_missing_modules()
        sys.path.insert(0, TOOLKIT)
        from bop_toolkit_lib import dataset_params, inout, misc
        cls.inout, cls.dataset_params, cls.misc = inout, dataset_params, misc
        cls.tmp = tempfile.TemporaryDirectory()
        # dataset_params knows only the benchmark's dataset names; "lm" gives the generic templates.
        cls.root = os.path.join(cls.tmp.name, "lm")
        subprocess.run([layout.FIXTURE] + cls.FIXTURE_ARGS + [cls.root], check=True)
        cls.split = dataset_params.get_split_params(cls.tmp.name, "lm", "train", "pbr")
        cls.models = dataset_params.get_model_params(cls.tmp.name, "lm")
        cls.scenes = inout.load_json(os.path.join(cls.root, "scenes.json"))["scenes"]

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_split_folder_is_the_one_dataset_params_names(self):
        self.assertEqual(os.path.basename(self.split["split_path"]), layout.SPLIT)
        self.assertEqual(sorted(os.listdir(self.split["split_path"])),
                         ["%06d" % e["scene_id"] for e in self.scenes])

    def test_camera_files_load_and_match_every_scene_of_their_sensor(self):
        # A plan of several sensors has camera_<sensor>.json, named as dataset_params names T-LESS's.
        os.symlink(self.root, os.path.join(self.tmp.name, "tless"))
        sensors = sorted({e["sensor"] for e in self.scenes})
        self.assertGreater(len(sensors), 1)
        for sensor in sensors:
            camera = self.dataset_params.get_camera_params(self.tmp.name, "tless", cam_type=sensor)
            for entry in (e for e in self.scenes if e["sensor"] == sensor):
                scene = self.inout.load_scene_camera(self.split["scene_camera_tpath"].format(scene_id=entry["scene_id"]))
                np.testing.assert_array_equal(camera["K"], scene[0]["cam_K"])
                self.assertEqual(camera["depth_scale"], scene[0]["depth_scale"])
                depth = self.inout.load_depth(self.split["depth_tpath"].format(scene_id=entry["scene_id"], im_id=0))
                self.assertEqual(camera["im_size"], (depth.shape[1], depth.shape[0]))

    def test_models_load_in_millimetres_and_match_models_info(self):
        info = self.inout.load_json(self.models["models_info_path"], keys_to_int=True)
        self.assertEqual(sorted(info), [1, 2])
        for obj_id, entry in info.items():
            model = self.inout.load_ply(self.models["model_tpath"].format(obj_id=obj_id))
            pts = model["pts"]
            self.assertGreater(len(model["faces"]), 0)
            np.testing.assert_allclose(pts.min(axis=0), [entry["min_x"], entry["min_y"], entry["min_z"]], atol=1e-3)
            np.testing.assert_allclose(pts.max(axis=0) - pts.min(axis=0),
                                       [entry["size_x"], entry["size_y"], entry["size_z"]], atol=1e-3)
            spread = np.linalg.norm(pts[:, None, :] - pts[None, :, :], axis=2).max()
            self.assertAlmostEqual(entry["diameter"], spread, places=2)

    def test_scene_files_load_and_agree(self):
        p = self.split
        for entry in self.scenes:
            scene_id = entry["scene_id"]
            cameras = self.inout.load_scene_camera(p["scene_camera_tpath"].format(scene_id=scene_id))
            gts = self.inout.load_scene_gt(p["scene_gt_tpath"].format(scene_id=scene_id))
            infos = self.inout.load_json(p["scene_gt_info_tpath"].format(scene_id=scene_id), keys_to_int=True)
            self.assertEqual(sorted(cameras), list(range(self.VIEWS)))
            self.assertEqual(sorted(cameras), sorted(gts))
            self.assertEqual(sorted(cameras), sorted(infos))
            for im_id, camera in cameras.items():
                self.assertEqual(camera["cam_K"].shape, (3, 3))
                self.assertEqual(camera["cam_R_w2c"].shape, (3, 3))
                self.assertEqual(camera["cam_t_w2c"].shape, (3, 1))
                depth = self.inout.load_depth(p["depth_tpath"].format(scene_id=scene_id, im_id=im_id))
                self.assertEqual(depth.ndim, 2)
                depth_mm = depth * camera["depth_scale"]
                # BOP's gray/ modality: one 16-bit channel the size of the depth, lit where there is depth.
                gray = np.asarray(self.inout.load_im(p["gray_tpath"].format(scene_id=scene_id, im_id=im_id)))
                self.assertEqual(gray.shape, depth.shape)
                self.assertGreater(int(gray.max()), 255)  # 16 bits
                np.testing.assert_array_equal(gray > 0, depth_mm > 0)
                for gt_id, (gt, info) in enumerate(zip(gts[im_id], infos[im_id])):
                    r = gt["cam_R_m2c"]
                    self.assertEqual(r.dtype, np.float64)
                    # Double precision: orthonormal to far below what a float32 could hold.
                    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
                    self.assertEqual(gt["cam_t_m2c"].shape, (3, 1))
                    mask = self.inout.load_im(p["mask_visib_tpath"].format(scene_id=scene_id, im_id=im_id, gt_id=gt_id))
                    visible = np.asarray(mask) > 0
                    self.assertEqual(info["px_count_visib"], int(visible.sum()))
                    self.assertEqual(info["px_count_valid"], int((visible & (depth_mm > 0)).sum()))
                    self.assertGreaterEqual(info["px_count_all"], info["px_count_visib"])
                    full = np.asarray(self.inout.load_im(p["mask_tpath"].format(
                        scene_id=scene_id, im_id=im_id, gt_id=gt_id))) > 0
                    self.assertEqual(info["px_count_all"], int(full.sum()))
                    self.assertTrue(np.all(full[visible]))
                    fys, fxs = np.nonzero(full)
                    self.assertEqual(info["bbox_obj"], [int(v) for v in self.misc.calc_2d_bbox(fxs, fys)])
                    ys, xs = np.nonzero(visible)
                    self.assertEqual(info["bbox_visib"], [int(v) for v in self.misc.calc_2d_bbox(xs, ys)])


class BopToolkitReadsAMultiViewDatasetTest(BopToolkitReadsTheDatasetTest):
    FIXTURE_ARGS = ["--views"]
    VIEWS = 3


if __name__ == "__main__":
    unittest.main()
