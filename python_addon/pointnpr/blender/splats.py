"""3D Gaussian splats on Blender objects (a 3DGS PLY or an SPZ imported by
File > Import > Point Cloud): the importer writes a capture's parameters as
point attributes of its one object, with their meaning, and the sync reads
them back for the gaussians mark (sync.cloud_for, source attribute
"gaussians").

Point attributes (all POINT domain):
  "opacity"          FLOAT          in [0, 1]
  "scale"            FLOAT_VECTOR   standard deviations along the splat's axes
  "rotation"         QUATERNION     w, x, y, z (Blender 4.2+; FLOAT_COLOR before)
  "sh_0" .. "sh_<K-1>" FLOAT_VECTOR the SH coefficients r, g, b, K = (degree + 1)^2
plus the colour attribute every scan gets, the DC term's colour, and the
mesh's custom property "pointnpr_antialiased" (1: trained with
anti-aliasing, SPZ's flag).

Blender 5.3's own splat point clouds (PointCloud type 'GAUSSIAN_SPLAT', as
its glTF importer makes them from KHR_gaussian_splatting) are read too:
"rotation" (QUATERNION), "scale" (FLOAT_VECTOR, linear), "radiance:base"
(FLOAT4: the DC coefficients r, g, b and the opacity in [0, 1]) and
"radiance:sh_0" .. (FLOAT_VECTOR, the higher bands in the object's frame).
In such a Blender the importer writes that kind of point cloud
(add_point_cloud_object) instead of a mesh, plus the scan colour "Col" and
"pointnpr_antialiased" as above."""
import bpy
import numpy as np

# The source attribute name the sync reads them under.
SOURCE = "gaussians"
_ROTATION_TYPES = {'QUATERNION': "value", 'FLOAT_COLOR': "color"}
_FLOAT4_TYPES = {'FLOAT4': "vector", 'FLOAT_COLOR': "color"}


def wanted(core_style):
    """Whether ``core_style`` (a pointnpr.Style) reads splats: its mark is
    gaussians, or another mark asks for a splat's footprint or opacity."""
    return core_style.mark[0] == "gaussians" or any(
        a.split(":")[0] in ("splat_radius", "splat_opacity") for a in core_style.attributes)


def write(mesh, opacity, scales, rotations, sh, antialiased=False):
    """Adds the splat attributes to ``mesh`` (one row per vertex)."""
    mesh["pointnpr_antialiased"] = int(bool(antialiased))
    n = len(mesh.vertices)
    attr = mesh.attributes.new("opacity", 'FLOAT', 'POINT')
    attr.data.foreach_set("value", np.ascontiguousarray(opacity, np.float32).reshape(-1))
    attr = mesh.attributes.new("scale", 'FLOAT_VECTOR', 'POINT')
    attr.data.foreach_set("vector", np.ascontiguousarray(scales, np.float32).reshape(-1))
    try:
        attr = mesh.attributes.new("rotation", 'QUATERNION', 'POINT')
    except TypeError:  # before Blender 4.2: four floats in a colour attribute
        attr = mesh.attributes.new("rotation", 'FLOAT_COLOR', 'POINT')
    attr.data.foreach_set(_ROTATION_TYPES[attr.data_type], np.ascontiguousarray(rotations, np.float32).reshape(-1))
    sh = np.asarray(sh, np.float32).reshape(n, -1, 3)
    for k in range(sh.shape[1]):
        attr = mesh.attributes.new("sh_%d" % k, 'FLOAT_VECTOR', 'POINT')
        attr.data.foreach_set("vector", np.ascontiguousarray(sh[:, k]).reshape(-1))


def native_point_clouds():
    """Whether this Blender has its own splat point clouds (5.3+: PointCloud
    type 'GAUSSIAN_SPLAT')."""
    prop = bpy.types.PointCloud.bl_rna.properties.get("type") if hasattr(bpy.types, "PointCloud") else None
    return prop is not None and 'GAUSSIAN_SPLAT' in {item.identifier for item in prop.enum_items}


def add_point_cloud_object(job, name, collection, positions, colors, opacity, scales, rotations, sh,
                           antialiased=False):
    """One object holding a Blender 5.3 splat point cloud (module docstring),
    made and tracked by ``job`` (importer.PointObjectJob) so that a failed
    import removes it again."""
    from .importer import add_color_attribute

    n = len(positions)
    cloud = job.track(bpy.data.pointclouds, bpy.data.pointclouds.new(name))
    cloud.resize(n)
    cloud.attributes["position"].data.foreach_set("vector", np.ascontiguousarray(positions, np.float32).reshape(-1))
    cloud.type = 'GAUSSIAN_SPLAT'
    cloud["pointnpr_antialiased"] = int(bool(antialiased))
    sh = np.asarray(sh, np.float32).reshape(n, -1, 3)
    # The DC term and the opacity in one FLOAT4, as Blender's own importers store them.
    base = np.empty((n, 4), np.float32)
    base[:, :3] = sh[:, 0]
    base[:, 3] = np.asarray(opacity, np.float32).reshape(-1)
    columns = [("rotation", 'QUATERNION', "value", rotations), ("scale", 'FLOAT_VECTOR', "vector", scales),
               ("radiance:base", 'FLOAT4', "vector", base)]
    columns += [("radiance:sh_%d" % (k - 1), 'FLOAT_VECTOR', "vector", sh[:, k]) for k in range(1, sh.shape[1])]
    for attr_name, data_type, prop, values in columns:
        attr = cloud.attributes.new(attr_name, data_type, 'POINT')
        attr.data.foreach_set(prop, np.ascontiguousarray(values, np.float32).reshape(-1))
    if colors is not None:
        add_color_attribute(cloud, colors)
    obj = job.track(bpy.data.objects, bpy.data.objects.new(name, cloud))
    collection.objects.link(obj)
    job.objects.append(obj)
    return obj


def _values(attrs, name, types, n, width):
    attr = attrs.get(name)
    if attr is None or attr.domain != 'POINT' or attr.data_type not in types or len(attr.data) != n:
        return None
    values = np.empty(n * width, dtype=np.float32)
    attr.data.foreach_get(types[attr.data_type], values)
    return values.reshape(n, width) if width > 1 else values


def read(obj):
    """The splat parameters of ``obj`` as pointnpr.PointCloud's keywords
    (opacity, scales, rotations, sh, sh_degree), or None where it has none."""
    attrs = getattr(obj.data, "attributes", None)
    if not attrs:
        return None
    if attrs.get("opacity") is None:
        return _read_radiance(obj, attrs)
    n = len(attrs["opacity"].data)
    opacity = _values(attrs, "opacity", {'FLOAT': "value"}, n, 1)
    scales = _values(attrs, "scale", {'FLOAT_VECTOR': "vector"}, n, 3)
    rotations = _values(attrs, "rotation", _ROTATION_TYPES, n, 4)
    if opacity is None or scales is None or rotations is None:
        return None
    bands = []
    while len(bands) < 16:
        values = _values(attrs, "sh_%d" % len(bands), {'FLOAT_VECTOR': "vector"}, n, 3)
        if values is None:
            break
        bands.append(values)
    degree = {1: 0, 4: 1, 9: 2, 16: 3}.get(len(bands))
    if degree is None:
        return None
    return {"opacity": opacity, "scales": scales, "rotations": rotations,
            "sh": np.ascontiguousarray(np.stack(bands, axis=1).reshape(n, -1)), "sh_degree": degree,
            "antialiased": bool(obj.data.get("pointnpr_antialiased", 0))}


def _read_radiance(obj, attrs):
    """Blender 5.3's splat attributes (module docstring), or None."""
    base = attrs.get("radiance:base")
    if base is None:
        return None
    n = len(base.data)
    base = _values(attrs, "radiance:base", _FLOAT4_TYPES, n, 4)
    scales = _values(attrs, "scale", {'FLOAT_VECTOR': "vector"}, n, 3)
    rotations = _values(attrs, "rotation", _ROTATION_TYPES, n, 4)
    if base is None or scales is None or rotations is None:
        return None
    bands = [np.ascontiguousarray(base[:, :3])]
    while len(bands) < 16:
        values = _values(attrs, "radiance:sh_%d" % (len(bands) - 1), {'FLOAT_VECTOR': "vector"}, n, 3)
        if values is None:
            break
        bands.append(values)
    degree = {1: 0, 4: 1, 9: 2, 16: 3}.get(len(bands))
    if degree is None:
        return None
    return {"opacity": np.ascontiguousarray(base[:, 3]), "scales": scales, "rotations": rotations,
            "sh": np.ascontiguousarray(np.stack(bands, axis=1).reshape(n, -1)), "sh_degree": degree,
            "antialiased": bool(obj.data.get("pointnpr_antialiased", 0))}
