"""Python values -> vscan.v1 messages: vectors, poses, units, formats, fields."""

import math
import os

from ._stubs import common_pb2, robot_pb2, scan_pb2, scene_pb2

UNITS = {
    "m": common_pb2.LENGTH_UNIT_METRE,
    "cm": common_pb2.LENGTH_UNIT_CENTIMETRE,
    "mm": common_pb2.LENGTH_UNIT_MILLIMETRE,
    "in": common_pb2.LENGTH_UNIT_INCH,
    "ft": common_pb2.LENGTH_UNIT_FOOT,
}

FORMATS = {
    "ply": scene_pb2.MESH_FORMAT_PLY,
    "obj": scene_pb2.MESH_FORMAT_OBJ,
    "stl": scene_pb2.MESH_FORMAT_STL,
}

FIELDS = {
    "position": scan_pb2.POINT_FIELD_POSITION,
    "normal": scan_pb2.POINT_FIELD_NORMAL,
    "range": scan_pb2.POINT_FIELD_RANGE,
    "intensity": scan_pb2.POINT_FIELD_INTENSITY,
    "instance": scan_pb2.POINT_FIELD_INSTANCE_ID,
    "instance_id": scan_pb2.POINT_FIELD_INSTANCE_ID,
    "pixel": scan_pb2.POINT_FIELD_PIXEL,
    "clean": scan_pb2.POINT_FIELD_CLEAN_POSITION,
    "clean_position": scan_pb2.POINT_FIELD_CLEAN_POSITION,
    "incidence": scan_pb2.POINT_FIELD_INCIDENCE_ANGLE,
    "incidence_angle": scan_pb2.POINT_FIELD_INCIDENCE_ANGLE,
    "status": scan_pb2.POINT_FIELD_STATUS,
    "estimated_normal": scan_pb2.POINT_FIELD_ESTIMATED_NORMAL,
    "estimated-normal": scan_pb2.POINT_FIELD_ESTIMATED_NORMAL,
}

# PointStatus values by short name, for reading ScanResult.statuses.
STATUSES = {
    "measured": scan_pb2.POINT_STATUS_MEASURED,
    "outlier": scan_pb2.POINT_STATUS_OUTLIER,
    "flying_pixel": scan_pb2.POINT_STATUS_FLYING_PIXEL,
    "out_of_range": scan_pb2.POINT_STATUS_REJECTED_OUT_OF_RANGE,
    "shadowed": scan_pb2.POINT_STATUS_REJECTED_SHADOWED,
    "grazing": scan_pb2.POINT_STATUS_REJECTED_GRAZING,
    "dim": scan_pb2.POINT_STATUS_REJECTED_DIM,
    "unlit": scan_pb2.POINT_STATUS_REJECTED_UNLIT,
    "dark": scan_pb2.POINT_STATUS_REJECTED_DARK,
    "saturated": scan_pb2.POINT_STATUS_REJECTED_SATURATED,
    "interreflection": scan_pb2.POINT_STATUS_REJECTED_INTERREFLECTION,
}

FRAMES = {"world": scan_pb2.FRAME_WORLD, "sensor": scan_pb2.FRAME_SENSOR}

IK_METHODS = {
    "default": robot_pb2.IK_METHOD_DEFAULT,
    "gradient": robot_pb2.IK_METHOD_GRADIENT_DESCENT,
    "gradient_descent": robot_pb2.IK_METHOD_GRADIENT_DESCENT,
}

BACKENDS = {
    "raycast": scan_pb2.SCAN_BACKEND_RAYCAST,
    "depth": scan_pb2.SCAN_BACKEND_RASTER_DEPTH,
    "colour": scan_pb2.SCAN_BACKEND_RASTER_COLOUR,
    "color": scan_pb2.SCAN_BACKEND_RASTER_COLOUR,
}


def _lookup(table, value, what):
    if isinstance(value, int):
        return value
    try:
        return table[str(value).lower()]
    except KeyError:
        raise ValueError(f"{what}: unknown value {value!r} (one of {', '.join(sorted(table))})") from None


_MATERIAL_VALUES = ("diffuse_albedo", "metallic", "roughness", "specular_reflectance")


def material(value):
    """A Material message from a preset name (str), a mapping with all four of diffuse_albedo,
    metallic, roughness and specular_reflectance, or a Material message; None stays None.
    The server checks names and ranges (roughness in (0, 1], the others in [0, 1])."""
    if value is None or isinstance(value, scene_pb2.Material):
        return value
    if isinstance(value, str):
        return scene_pb2.Material(preset=value)
    if hasattr(value, "keys"):
        keys = set(value.keys())
        if keys != set(_MATERIAL_VALUES):
            raise ValueError(
                "material: give all of %s (got %s)" % (", ".join(_MATERIAL_VALUES), ", ".join(sorted(keys)))
            )
        values = scene_pb2.MaterialValues(**{k: float(value[k]) for k in _MATERIAL_VALUES})
        return scene_pb2.Material(values=values)
    raise TypeError("material: a preset name, a mapping of values or a Material, not %s" % type(value).__name__)


def returned_light(value, message):
    """Sets message (a ReturnedLight) from True (every default) or a mapping of its fields
    (emitter_w_per_sr, exposure_s, ...; 0 or absent takes the default); None and False leave it
    unset. Returns whether it was set. The server checks the ranges."""
    if value is None or value is False:
        return False
    message.SetInParent()
    if value is not True:
        fields = message.DESCRIPTOR.fields_by_name
        for key, number in dict(value).items():
            if key not in fields:
                raise ValueError(f"returned_light: unknown key {key!r} (one of {', '.join(fields)})")
            whole = fields[key].cpp_type in (fields[key].CPPTYPE_UINT32, fields[key].CPPTYPE_UINT64,
                                             fields[key].CPPTYPE_INT32, fields[key].CPPTYPE_INT64)
            setattr(message, key, int(number) if whole else float(number))
    return True


def unit(value):
    return _lookup(UNITS, value, "unit")


def mesh_format(value=None, path=None):
    """An explicit format, or the one the file extension names."""
    if value is None and path is not None:
        value = os.path.splitext(path)[1].lstrip(".")
    return _lookup(FORMATS, value, "format")


def fields(values):
    return [_lookup(FIELDS, v, "fields") for v in values]


def frame(value):
    return _lookup(FRAMES, value, "frame")


def backend(value):
    return _lookup(BACKENDS, value, "backend")


def ik_method(value):
    return _lookup(IK_METHODS, value, "method")


def numbers(values, what):
    """A flat list of finite floats."""
    out = [float(v) for v in values]
    if not all(math.isfinite(v) for v in out):
        raise ValueError(f"{what}: every value must be finite, got {out!r}")
    return out


def vector3(values, what="vector"):
    values = [float(v) for v in values]
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise ValueError(f"{what}: need 3 finite numbers, got {values!r}")
    return common_pb2.Vector3(x=values[0], y=values[1], z=values[2])


def bounds(low, high, what="bounds"):
    """Bounds from its min and max corners (x, y, z)."""
    return common_pb2.Bounds(min=vector3(low, f"{what} min"), max=vector3(high, f"{what} max"))


def matrix4(matrix, what="matrix"):
    """A 4x4 (nested sequence or numpy array) or 16 row-major values."""
    flat = [float(v) for row in matrix for v in (row if hasattr(row, "__iter__") else [row])]
    if len(flat) != 16:
        raise ValueError(f"{what}: need a 4x4 matrix (16 values), got {len(flat)}")
    return common_pb2.Matrix4(values=flat)


def pose(position=(0.0, 0.0, 0.0), quat=None, matrix=None):
    """A Pose from a translation and a unit quaternion (w, x, y, z), or from a 4x4 matrix."""
    if matrix is not None:
        if quat is not None:
            raise ValueError("pose: give quat or matrix, not both")
        return common_pb2.Pose(matrix=matrix4(matrix))
    w, x, y, z = (1.0, 0.0, 0.0, 0.0) if quat is None else [float(v) for v in quat]
    return common_pb2.Pose(
        quaternion=common_pb2.QuaternionPose(translation=vector3(position, "position"), qw=w, qx=x, qy=y, qz=z)
    )


def look_at(eye, target, up=(0.0, 0.0, 1.0)):
    return common_pb2.Pose(
        look_at=common_pb2.LookAt(eye=vector3(eye, "eye"), target=vector3(target, "target"), up=vector3(up, "up"))
    )
