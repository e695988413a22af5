"""Blender side of the Cycles oracle: renders one scene described by a JSON file with Cycles on the CPU
and writes the per-pixel radiance (W / (m^2 sr)) as a float32 .npy, top row first.

    blender -b --factory-startup -P bench/cycles_oracle/render_cycles.py -- scene.json out.npy

The JSON (written by cycles_oracle.py) holds the pinhole camera (width, height, fx, fy, cx, cy) at the
world origin looking along +z with +y down (vscan's sensor frame), the emitter (position, axis,
half_angle_deg, w_per_sr), the triangle meshes with vscan's four material values, and the render
settings (samples, max_bounces, seed, threads). The mappings and their limits are in README.md beside
this file.
"""

import json
import math
import sys
import time

import bpy
import numpy as np
from mathutils import Vector

MIN_ROUGHNESS = 0.02  # vscan's kMinRoughness (server/engine/sensor/brdf.h)


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)


def render_settings(scene, spec):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = int(spec["samples"])
    cycles.seed = int(spec.get("seed", 0))
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.light_sampling_threshold = 0.0  # no probabilistic termination of light samples
    bounces = int(spec["max_bounces"])
    cycles.max_bounces = bounces
    cycles.diffuse_bounces = bounces
    cycles.glossy_bounces = bounces
    cycles.transmission_bounces = 0
    cycles.volume_bounces = 0
    cycles.transparent_max_bounces = 0
    cycles.min_light_bounces = 0
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.blur_glossy = 0.0
    cycles.caustics_reflective = True
    cycles.caustics_refractive = False
    # Cycles' box filter is always one pixel wide; a Gaussian of width 0.01 px samples the pixel's
    # centre, as vscan's single ray per pixel does.
    cycles.pixel_filter_type = "GAUSSIAN"
    cycles.filter_width = 0.01
    scene.render.threads_mode = "FIXED"
    scene.render.threads = int(spec.get("threads", 2))
    scene.render.resolution_x = int(spec["width"])
    scene.render.resolution_y = int(spec["height"])
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world


def add_camera(scene, spec):
    width, height = int(spec["width"]), int(spec["height"])
    fx, fy, cx, cy = (float(spec[k]) for k in ("fx", "fy", "cx", "cy"))
    if abs(fx - fy) > 1e-9 * fx:
        raise SystemExit("render_cycles: Blender's camera needs square pixels (fx == fy)")
    camera = bpy.data.cameras.new("vscan")
    camera.sensor_fit = "HORIZONTAL"
    camera.sensor_width = 36.0
    camera.lens = fx * camera.sensor_width / width  # mm: focal length in pixels times the pixel pitch
    # Shifts are fractions of the larger image side; +x moves the frame right, +y up (image rows
    # grow downwards in vscan).
    side = max(width, height)
    camera.shift_x = (width / 2.0 - cx) / side
    camera.shift_y = (cy - height / 2.0) / side
    camera.clip_start = 1e-3
    camera.clip_end = 1e3
    obj = bpy.data.objects.new("vscan-camera", camera)
    scene.collection.objects.link(obj)
    # Blender's camera looks along its -z with +y up; vscan's along +z with +y down.
    obj.rotation_euler = (math.pi, 0.0, 0.0)
    scene.camera = obj


def add_emitter(scene, emitter):
    """A spot light of the emitter's cone. Cycles 3.4's spot light multiplies its intensity by the
    cosine of the angle to its axis (measured: spot / point equals that cosine), vscan's emitter is
    uniform within its cone: the light's node tree divides that cosine out. Power P of a point or
    spot light gives I = P / (4 pi) W/sr."""
    half = math.radians(float(emitter["half_angle_deg"]))
    if half >= math.pi / 2:
        raise SystemExit("render_cycles: a spot light's cone is at most 180 degrees wide")
    light = bpy.data.lights.new("vscan-emitter", "SPOT")
    light.spot_size = 2.0 * half
    light.spot_blend = 0.0
    light.show_cone = False
    light.shadow_soft_size = 0.0
    light.energy = 4.0 * math.pi * float(emitter["w_per_sr"])
    light.color = (1.0, 1.0, 1.0)
    light.use_nodes = True
    nodes, links = light.node_tree.nodes, light.node_tree.links
    coords = nodes.new("ShaderNodeTexCoord")  # "Normal": the direction of emission, light's frame
    unit = nodes.new("ShaderNodeVectorMath")
    unit.operation = "NORMALIZE"
    links.new(coords.outputs["Normal"], unit.inputs[0])
    axis = nodes.new("ShaderNodeSeparateXYZ")
    links.new(unit.outputs["Vector"], axis.inputs[0])
    cos_axis = nodes.new("ShaderNodeMath")
    cos_axis.operation = "ABSOLUTE"
    links.new(axis.outputs["Z"], cos_axis.inputs[0])
    inverse = nodes.new("ShaderNodeMath")
    inverse.operation = "DIVIDE"
    inverse.inputs[0].default_value = 1.0
    links.new(cos_axis.outputs["Value"], inverse.inputs[1])
    links.new(inverse.outputs["Value"], nodes["Emission"].inputs["Strength"])
    obj = bpy.data.objects.new("vscan-emitter", light)
    scene.collection.objects.link(obj)
    obj.location = Vector(emitter["position"])
    obj.rotation_mode = "QUATERNION"
    obj.rotation_quaternion = Vector(emitter["axis"]).normalized().to_track_quat("-Z", "Y")


class Nodes:
    """Shorthand for a material's node tree."""

    def __init__(self, tree):
        self.nodes, self.links = tree.nodes, tree.links

    def math(self, operation, a, b=None, clamp=False):
        node = self.nodes.new("ShaderNodeMath")
        node.operation = operation
        node.use_clamp = clamp
        for i, value in enumerate((a, b)):
            if value is None:
                continue
            if isinstance(value, (int, float)):
                node.inputs[i].default_value = float(value)
            else:
                self.links.new(value, node.inputs[i])
        return node.outputs["Value"]

    def vector(self, operation, a, b=None):
        node = self.nodes.new("ShaderNodeVectorMath")
        node.operation = operation
        for i, value in enumerate((a, b)):
            if value is None:
                continue
            if isinstance(value, (tuple, list)):
                node.inputs[i].default_value = tuple(float(v) for v in value)
            else:
                self.links.new(value, node.inputs[i])
        return node.outputs["Value" if operation == "DOT_PRODUCT" else "Vector"]

    def schlick(self, f0, cos_d):
        """vscan's SchlickFresnel: F0 + (F90 - F0) (1 - clamp(c, 0, 1))^5, F90 = min(1, 50 F0)."""
        f90 = min(1.0, 50.0 * f0)
        one_minus = self.math("SUBTRACT", 1.0, cos_d, clamp=True)
        return self.math("ADD", self.math("MULTIPLY", self.math("POWER", one_minus, 5.0), f90 - f0), f0)


def add_material(mesh, values, emitter_position):
    """vscan's BRDF: (1 - m) (1 - F(n.l)) (1 - F(n.v)) albedo / pi + GGX D G1 G1 F(h.v) / (4 n.l n.v),
    as a Diffuse BSDF plus a Glossy BSDF (GGX, single scattering; Cycles squares roughness into
    alpha as vscan does). Cycles has no Schlick term with vscan's F90 on the half vector, so the
    weights are computed per shading point from the emitter's position and the incoming ray: exact
    for the emitter's light, approximate for light arriving from other surfaces (README.md)."""
    albedo, metallic = float(values["diffuse_albedo"]), float(values["metallic"])
    roughness = max(float(values["roughness"]), MIN_ROUGHNESS)
    f0 = (1 - metallic) * float(values["specular_reflectance"]) + metallic * albedo
    material = bpy.data.materials.new("vscan-material")
    material.use_nodes = True
    tree = material.node_tree
    tree.nodes.clear()
    n = Nodes(tree)
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    output.target = "CYCLES"
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Roughness"].default_value = 0.0  # Lambert
    if f0 == 0.0:
        # F = 0 everywhere: exactly Lambertian, for every path.
        diffuse.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
        tree.links.new(diffuse.outputs["BSDF"], output.inputs["Surface"])
        mesh.materials.append(material)
        return
    geometry = tree.nodes.new("ShaderNodeNewGeometry")
    to_light = n.vector("NORMALIZE", n.vector("SUBTRACT", tuple(emitter_position), geometry.outputs["Position"]))
    to_viewer = geometry.outputs["Incoming"]
    half = n.vector("NORMALIZE", n.vector("ADD", to_light, to_viewer))
    cos_l = n.vector("DOT_PRODUCT", geometry.outputs["Normal"], to_light)
    cos_v = n.vector("DOT_PRODUCT", geometry.outputs["Normal"], to_viewer)
    cos_d = n.vector("DOT_PRODUCT", half, to_viewer)
    glossy = tree.nodes.new("ShaderNodeBsdfGlossy")
    glossy.distribution = "GGX"
    glossy.inputs["Roughness"].default_value = roughness
    tree.links.new(n.schlick(f0, cos_d), glossy.inputs["Color"])
    surface = glossy.outputs["BSDF"]
    if metallic < 1.0:
        weight = n.math("MULTIPLY", n.math("SUBTRACT", 1.0, n.schlick(f0, cos_l)),
                        n.math("SUBTRACT", 1.0, n.schlick(f0, cos_v)))
        tree.links.new(n.math("MULTIPLY", weight, (1 - metallic) * albedo), diffuse.inputs["Color"])
        both = tree.nodes.new("ShaderNodeAddShader")
        tree.links.new(diffuse.outputs["BSDF"], both.inputs[0])
        tree.links.new(glossy.outputs["BSDF"], both.inputs[1])
        surface = both.outputs["Shader"]
    tree.links.new(surface, output.inputs["Surface"])
    mesh.materials.append(material)


def add_meshes(scene, spec):
    for i, item in enumerate(spec["objects"]):
        mesh = bpy.data.meshes.new(f"object-{i}")
        mesh.from_pydata([tuple(v) for v in item["vertices"]], [], [tuple(f) for f in item["faces"]])
        mesh.update()
        for polygon in mesh.polygons:
            polygon.use_smooth = False  # vscan shades with each triangle's own normal
        add_material(mesh, item["material"], spec["emitter"]["position"])
        obj = bpy.data.objects.new(f"object-{i}", mesh)
        scene.collection.objects.link(obj)


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    if len(args) != 2:
        raise SystemExit("usage: blender -b --factory-startup -P render_cycles.py -- scene.json out.npy")
    with open(args[0]) as f:
        spec = json.load(f)
    scene = bpy.context.scene
    clear_scene()
    render_settings(scene, spec)
    add_camera(scene, spec)
    add_emitter(scene, spec["emitter"])
    add_meshes(scene, spec)
    exr = args[1] + ".exr"
    scene.render.filepath = exr
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.exr_codec = "ZIP"
    start = time.monotonic()
    bpy.ops.render.render(write_still=True)
    seconds = time.monotonic() - start
    image = bpy.data.images.load(exr)
    width, height = int(spec["width"]), int(spec["height"])
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(height, width, 4)[::-1]
    # White light on grey materials: the three channels are equal; green stands for the one band.
    np.save(args[1], np.ascontiguousarray(pixels[:, :, 1]))
    print("CYCLES_ORACLE " + json.dumps({"render_s": seconds, "version": bpy.app.version_string}), flush=True)


main()
