"""Helpers around the point cloud readers bound in ``_pointnpr``.

``pointnpr.read(path)`` returns a ``PointData``; ``to_cloud(data)`` (also
available as ``data.to_cloud()``) turns it into the renderer's ``PointCloud``.
``pointnpr.write(path, data)`` writes a ``PointData`` as binary PLY or LAS 1.4
(see "Writing" below).

Formats: LAS 1.0-1.4 and LAZ (LASzip, decoded in the project: point formats
0-10, COPC read as plain LAZ; ``read(path, progress=pointnpr.Progress())``
reports by chunk and can be cancelled), PLY (ascii / binary little and big endian; the vertex
element), PCD (ascii / binary / binary_compressed; NaN points of organized
clouds dropped), delimited text (.xyz .pts .txt .csv .asc) and E57 (ASTM
E2807: every scan with its pose applied, merged with a "scan_index"
attribute; ``read_e57_scans(path)`` gives one PointData per scan; see
docs/io.md#e57 for its attributes and metadata).

``PointData.positions`` is an (N, 3) float64 array of exact georeferenced
coordinates (LAS: integer * scale + offset). ``PointData.attributes`` holds
what the file has, one row per point:

=====================  ==============  =========================================
name                   dtype, shape    from
=====================  ==============  =========================================
colors                 uint8 (N, 3)    LAS RGB (16-bit files reduced with >> 8),
                                       PLY red/green/blue, PCD rgb/rgba, text
alpha                  uint8 (N,)      PLY alpha
intensity              float32 (N,)    LAS, PLY/PCD/text "intensity"
classification         uint8 (N,)      LAS (formats 6-10: all 8 bits), PLY/text
return_number,         uint8 (N,)      LAS
number_of_returns
user_data              uint8 (N,)      LAS
scan_angle             float32 (N,)    LAS, degrees
point_source_id        uint16 (N,)     LAS
gps_time               float64 (N,)    LAS formats 1, 3-10
nir                    uint16 (N,)     LAS formats 8, 10
normals                float32 (N, 3)  PLY nx/ny/nz, PCD normal_x/y/z, text
<extra bytes name>     native / f64    LAS extra bytes VLR (float64 when scaled)
<property name>        native          any other PLY scalar (its declared type)
<field/column name>    float32         any other PCD/text field
=====================  ==============  =========================================

Gaussian splats: a 3DGS PLY (recognised by its f_dc_*, opacity, scale_*
and rot_* properties) and an SPZ file (versions 2 to 4) give the same
attributes, with their meaning rather than their storage: "opacity" float32
(N,) after the sigmoid, "scales" float32 (N, 3) standard deviations after
exp, "rotations" float32 (N, 4) unit quaternions w, x, y, z, "sh" float32
(N, 3K) the K = (degree + 1)^2 spherical-harmonic coefficients, each r, g, b
(DC first; display-referred sRGB as trained), and "colors" uint8 (N, 3) =
0.5 + 0.2820948 DC, clamped; metadata "gaussian_splats" = 1 and
"sh_degree". SPZ's right-up-back axes are turned into the PLY's (y and z
negated) so both formats of one capture coincide.

``PointData.metadata`` always has "format" ("las", "ply", "pcd", "text") and
"point_count"; LAS adds "version", "point_format", "point_record_length",
"scale", "offset", "bounds_min", "bounds_max", "crs_wkt" and "crs_epsg" (when
the file has them), "color_bits" (8 or 16), "colors_all_zero" (colour fields
present but all zero: no "colors" attribute), "extra_bytes_undescribed",
"waveform_ignored"; PLY adds "encoding", "elements", "comments"; PCD adds
"encoding", "width", "height", "organized"; any reader adds
"dropped_nonfinite" when it removed points with NaN/inf coordinates.

``pointnpr.ReadError`` (a ValueError) names the file, the reason and, where it
applies, the byte offset; also available as ``.file``, ``.reason`` and
``.byte_offset``.

Writing: ``pointnpr.write(path, data)`` picks the format from the extension.

- ``.ply``: binary little endian; x/y/z as float64 (exact), every attribute
  column in its own dtype ("colors" as red/green/blue, "normals" as nx/ny/nz,
  other (N, k) attributes as name_0 .. name_k-1; 64-bit integers as float64
  when exact, refused otherwise); metadata "comments" as comment lines.
- ``.las``: LAS 1.4, point format 6, 7 (with "colors") or 8 (with "nir").
  Coordinates keep the source's "scale"/"offset" when these hold every point
  exactly (LAS -> LAS is lossless), else the finest power-of-ten grid that
  covers the extent (error <= scale / 2, at most 0.05 mm below ~429 km of
  extent). The LAS fields (intensity, return_number, number_of_returns,
  classification, user_data, scan_angle (0.006 degree steps),
  point_source_id, gps_time, colors, nir) take the attributes of those names,
  rounded, and refuse values out of the field's range; every other attribute
  goes to extra bytes in its dtype (described by an extra-bytes VLR; more than
  3 columns are split into groups of 3). "crs_wkt" is written as a WKT VLR,
  "crs_epsg" as a GeoKeyDirectory.

Errors (non-finite coordinates, values a field cannot hold, unwritable path)
raise ``pointnpr.Error``; no partial file is left behind.
"""
import numpy as _np

from . import _pointnpr

__all__ = ["read", "read_e57_scans", "write", "to_cloud", "ReadError", "PointData", "RENDERED_ATTRIBUTES"]

read = _pointnpr.read
read_e57_scans = _pointnpr.read_e57_scans
write = _pointnpr.write
ReadError = _pointnpr.ReadError
PointData = _pointnpr.PointData

# Attributes of a PointData that PointCloud takes, with the dtype it wants.
RENDERED_ATTRIBUTES = {
    "colors": _np.uint8,
    "intensity": _np.float32,
    "classification": _np.uint8,
}


def to_cloud(data):
    """PointCloud (pointnpr.PointCloud) from a PointData: positions plus the
    colors, intensity and classification the file has (others are dropped),
    a splat capture's opacity, scales, rotations and SH (see "Gaussian
    splats" above), and where the sensor stood when the file says (an organized PCD frame)."""
    kwargs = {}
    attrs = data.attributes
    for name, dtype in RENDERED_ATTRIBUTES.items():
        values = attrs.get(name)
        if values is not None:
            kwargs[name] = _np.ascontiguousarray(values, dtype=dtype)
    if data.metadata.get("gaussian_splats"):  # 3D Gaussian splats (3DGS PLY, SPZ): their parameters too
        for name in ("opacity", "scales", "rotations", "sh"):
            kwargs[name] = _np.ascontiguousarray(attrs[name], dtype=_np.float32)
        kwargs["sh_degree"] = int(data.metadata["sh_degree"])
        kwargs["antialiased"] = bool(data.metadata.get("antialiased", 0))  # SPZ's Mip-Splatting flag
    sensor = data.metadata.get("sensor_origin")  # a depth camera's frame: its normals face the sensor
    if sensor is not None:
        kwargs["sensor"] = tuple(float(v) for v in sensor)
    return _pointnpr.PointCloud(_np.ascontiguousarray(data.positions, dtype=_np.float64), **kwargs)
