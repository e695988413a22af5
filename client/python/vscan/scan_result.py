"""Assembling a Scan stream (header, chunks, pixel rows, statistics) into numpy arrays."""

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ._stubs import scan_pb2

_F32 = np.dtype("<f4")
_U32 = np.dtype("<u4")
_U8 = np.dtype("u1")
_U16 = np.dtype("<u2")


@dataclass
class ScanResult:
    """One scan. Arrays have one row per point; absent fields are None."""

    header: scan_pb2.ScanHeader
    stats: scan_pb2.ScanStatistics
    positions: np.ndarray  # (N, 3) float32
    normals: Optional[np.ndarray] = None  # (N, 3) float32
    ranges: Optional[np.ndarray] = None  # (N,) float32
    intensities: Optional[np.ndarray] = None  # (N,) float32
    instance_ids: Optional[np.ndarray] = None  # (N,) uint32
    pixels: Optional[np.ndarray] = None  # (N,) uint32
    clean_positions: Optional[np.ndarray] = None  # (N, 3) float32, before noise and artefacts
    incidence_angles: Optional[np.ndarray] = None  # (N,) float32, radians
    statuses: Optional[np.ndarray] = None  # (N,) uint8, scan_pb2.PointStatus values
    estimated_normals: Optional[np.ndarray] = None  # (N, 3) float32
    # With pixel_images, (height, width) images: each pixel's PointStatus (0 where the ray met no
    # surface) and the grey image (65535 at full scale).
    reasons: Optional[np.ndarray] = None  # uint8
    gray: Optional[np.ndarray] = None  # uint16

    def __len__(self):
        return int(self.positions.shape[0])

    @property
    def objects(self):
        """With ground_truth: the scene objects in view (scan_pb2.ObjectTruth), by instance id."""
        return list(self.stats.objects)


# chunk attribute, header field, dtype, values per point
_LAYOUT = (
    ("positions", scan_pb2.POINT_FIELD_POSITION, _F32, 3),
    ("normals", scan_pb2.POINT_FIELD_NORMAL, _F32, 3),
    ("ranges", scan_pb2.POINT_FIELD_RANGE, _F32, 1),
    ("intensities", scan_pb2.POINT_FIELD_INTENSITY, _F32, 1),
    ("instance_ids", scan_pb2.POINT_FIELD_INSTANCE_ID, _U32, 1),
    ("pixels", scan_pb2.POINT_FIELD_PIXEL, _U32, 1),
    ("clean_positions", scan_pb2.POINT_FIELD_CLEAN_POSITION, _F32, 3),
    ("incidence_angles", scan_pb2.POINT_FIELD_INCIDENCE_ANGLE, _F32, 1),
    ("statuses", scan_pb2.POINT_FIELD_STATUS, _U8, 1),
    ("estimated_normals", scan_pb2.POINT_FIELD_ESTIMATED_NORMAL, _F32, 3),
)

# Server default when a header lists no fields.
_DEFAULT_FIELDS = {
    scan_pb2.POINT_FIELD_POSITION,
    scan_pb2.POINT_FIELD_NORMAL,
    scan_pb2.POINT_FIELD_RANGE,
    scan_pb2.POINT_FIELD_INTENSITY,
    scan_pb2.POINT_FIELD_INSTANCE_ID,
}


# Upper bound on points allocated up front, so a bogus header cannot exhaust memory by itself.
_MAX_RESERVED_POINTS = 1 << 26


class ScanAssembler:
    """Feed it ScanResponse messages in order; result() checks counts and returns the arrays.

    Each field's chunks are copied once, straight into one array allocated when the header
    arrives (for the announced points or, when a streamed scan announces none, one per ray:
    pages no point reaches are never touched); the result holds views of those arrays.
    """

    def __init__(self, on_progress=None):
        self._header = None
        self._stats = None
        self._arrays = {}
        self._points = 0
        self._on_progress = on_progress
        self._reasons = None
        self._gray = None
        self._rows = 0

    def add(self, message):
        part = message.WhichOneof("part")
        if part == "header":
            if self._header is not None:
                raise ValueError("scan stream: second header")
            self._header = message.header
            present = set(self._header.fields) or set(_DEFAULT_FIELDS)
            present.add(scan_pb2.POINT_FIELD_POSITION)
            room = min(self._header.points or self._header.rays, _MAX_RESERVED_POINTS)
            self._arrays = {name: np.empty(room * width, dtype=dtype)
                            for name, field, dtype, width in _LAYOUT if field in present}
            if self._header.pixel_images:
                shape = (self._header.height, self._header.width)
                if shape[0] * shape[1] > _MAX_RESERVED_POINTS:
                    raise ValueError(f"scan stream: pixel images of {shape[1]} x {shape[0]} pixels")
                self._reasons = np.zeros(shape, dtype=_U8)
                self._gray = np.zeros(shape, dtype=_U16)
        elif part == "pixel_rows":
            self._add_rows(message.pixel_rows)
        elif part == "chunk":
            if self._header is None:
                raise ValueError("scan stream: chunk before the header")
            chunk = message.chunk
            end = self._points + chunk.count
            if self._header.points and end > self._header.points:
                raise ValueError(f"scan stream: more points than the header announced ({self._header.points})")
            for name, _, dtype, width in _LAYOUT:
                if name not in self._arrays:
                    continue
                data = getattr(chunk, name)
                if len(data) != chunk.count * dtype.itemsize * width:
                    raise ValueError(
                        f"chunk {chunk.index}.{name}: expected {chunk.count * dtype.itemsize * width} bytes, "
                        f"got {len(data)}"
                    )
                array = self._arrays[name]
                if end * width > array.shape[0]:
                    array = self._arrays[name] = _grown(array, end * width)
                array[self._points * width:end * width] = np.frombuffer(data, dtype=dtype)
            self._points = end
            if self._on_progress:
                self._on_progress(self._points, self._header.points)
        elif part == "statistics":
            if self._stats is not None:
                raise ValueError("scan stream: second statistics")
            self._stats = message.statistics

    def result(self):
        if self._header is None:
            raise ValueError("scan stream: ended without a header")
        if self._stats is None:
            raise ValueError("scan stream: ended without statistics")
        # A streamed scan's header announces no count (0); its statistics carry the total.
        expected = self._header.points or self._stats.streamed_points
        if self._points != expected:
            raise ValueError(f"scan stream: received {self._points} of {expected} points")
        if self._reasons is not None and self._rows != self._reasons.shape[0]:
            raise ValueError(f"scan stream: received {self._rows} of {self._reasons.shape[0]} rows of pixel images")
        arrays = {}
        for name, _, _, width in _LAYOUT:
            if name in self._arrays:
                array = self._arrays[name][:self._points * width]
                arrays[name] = array.reshape(-1, 3) if width == 3 else array
        return ScanResult(header=self._header, stats=self._stats, reasons=self._reasons, gray=self._gray, **arrays)

    def _add_rows(self, rows):
        if self._reasons is None:
            raise ValueError("scan stream: pixel rows the header did not announce")
        if self._stats is not None:
            raise ValueError("scan stream: pixel rows after the statistics")
        height, width = self._reasons.shape
        if rows.first_row != self._rows or rows.row_count == 0 or rows.row_count > height - self._rows:
            raise ValueError(f"scan stream: pixel rows {rows.first_row} + {rows.row_count} after {self._rows} of {height}")
        count = rows.row_count * width
        if len(rows.reasons) != count or len(rows.gray) != 2 * count:
            raise ValueError("scan stream: pixel rows of the wrong size")
        end = self._rows + rows.row_count
        self._reasons[self._rows:end] = np.frombuffer(rows.reasons, dtype=_U8).reshape(-1, width)
        self._gray[self._rows:end] = np.frombuffer(rows.gray, dtype=_U16).reshape(-1, width)
        self._rows = end


def _grown(array, needed):
    """Only when a header announced less room than the chunks need."""
    bigger = np.empty(max(needed, 2 * array.shape[0]), dtype=array.dtype)
    bigger[:array.shape[0]] = array
    return bigger
