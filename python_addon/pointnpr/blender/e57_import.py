"""E57 files for the importer: the scans read apart (pointnpr.read_e57_scans),
given normals (the file's, or a structured scan's grid normals), then
merged as pointnpr.read merges them. ``core`` is the pointnpr module."""
import numpy as np


def scan_normals(core, scan):
    """(N,3) float32 normals of one E57 scan (a PointData of
    read_e57_scans), or None: the file's own (libE57's normals extension),
    else, for a structured scan (row_index and column_index), from its grid,
    facing its scanner (pointnpr.grid_normals): faster than a neighbour
    search, and oriented."""
    attrs = dict(scan.attributes)
    if attrs.get("normals") is not None:
        return np.asarray(attrs["normals"], np.float32)
    rows, columns = attrs.get("row_index"), attrs.get("column_index")
    if rows is None or columns is None or scan.num_points == 0:
        return None
    return core.grid_normals(scan.positions, np.asarray(rows, np.int64), np.asarray(columns, np.int64),
                             np.asarray(scan.metadata["pose_translation"], np.float64))


def read_e57(core, path, progress=None):
    """An E57 file's scans as one PointData, as pointnpr.read merges them
    (the attributes every scan has, "scan_index", "scan_names"), plus
    "normals" when a scan has normals (scan_normals; NaN rows for the
    scans without)."""
    scans = core.read_e57_scans(path, progress=progress)
    if not scans:
        return core.PointData(np.zeros((0, 3)), {}, {"format": "e57"})
    attrs = {}
    for name in dict(scans[0].attributes):
        columns = [dict(s.attributes).get(name) for s in scans]
        if all(c is not None and c.dtype == columns[0].dtype and c.shape[1:] == columns[0].shape[1:]
               for c in columns):
            attrs[name] = np.concatenate(columns)
    normals = [scan_normals(core, s) for s in scans]
    attrs.pop("normals", None)
    if any(n is not None for n in normals):  # NaN rows for the scans without
        attrs["normals"] = np.concatenate([np.full((s.num_points, 3), np.nan, np.float32) if n is None else n
                                           for s, n in zip(scans, normals)])
    del normals
    attrs["scan_index"] = np.repeat(np.arange(len(scans), dtype=np.uint32), [s.num_points for s in scans])
    first = dict(scans[0].metadata)
    metadata = {key: first[key] for key in ("version", "coordinate_metadata", "images2d", "images2d_count")
                if key in first}
    metadata.update(format="e57", scan_count=len(scans),
                    scan_names="\n".join(str(s.metadata.get("scan_name", "")) for s in scans))
    positions = np.concatenate([s.positions for s in scans])
    del scans
    return core.PointData(positions, attrs, metadata)
