"""Render a vdbappear medium with Blender Cycles (CPU) in the scene vdb_render would build.

Run headless, never imported:

  blender -b -noaudio --factory-startup --python-exit-code 1 -P scripts/blender_scene.py -- \
      --vdb FILE.vdb --out OUT.exr [--res 256 | --res WxH] --spp N \
      --camera-pos x,y,z --camera-target x,y,z [--camera-up 0,0,1] [--fov 30] \
      [--env R | --env R,G,B] [--sun DX,DY,DZ,STRENGTH] [--threads T] [--seed S] \
      [--openvdb-voxel-centres] [--force] [--step-rate R] [--volume-bounces N]
      [--blackbody GRID[:KELVIN[:INTENSITY]]] [--emission-grid]

Writes OUT.exr (linear scene-referred RGB, 32-bit float, no view transform) and prints one JSON line
on stdout, e.g. {"seconds": 12.3, "spp": 64, ...}. Blender prints its own lines around it
("Fra:1 Mem:...", "Blender quit"): take the line that starts with '{'. Exit status 2 on a refused
input; pass --python-exit-code 1 so that an unexpected Python error also fails the command.

Written for Debian 12's blender 3.4.1; settings that a given version lacks are skipped with a note on
stderr (e.g. use_light_tree exists from 3.5 on). Cycles is left at its default volume algorithm of
that version (3.4: ray marching, step = voxel size x volume_step_rate 1.0, volume_max_steps 1024).

Unit conventions, matched to vdb_render (libvdbappear/render/*.h, docs/medium.md):

* Medium. vdb_render: sigma_t = rho (FloatGrid "density", per world unit), sigma_s = albedo * rho,
  sigma_a = (1 - albedo) * rho, albedo from the Vec3SGrid (or grey FloatGrid) "albedo", default 1;
  phase HG with g from grid "hg_g", else file metadata "hg_g", else 0 (isotropic).
  Cycles (intern/cycles/kernel/svm/closure.h, svm_node_closure_volume): a Volume Scatter node with
  colour C and density D adds a HG closure of weight C*D (= sigma_s) and extinction C*D; a Volume
  Absorption node with colour C and density D adds extinction (1 - C)*D (= sigma_a). So both nodes
  take C = albedo attribute and D = density attribute, added together:
      sigma_s = albedo*rho,  sigma_a = (1 - albedo)*rho,  sigma_t = sigma_s + sigma_a = rho.
  With float grids sigma_s_r, _g, _b = rho*albedo (scripts/premultiply_albedo.py) the colour is
  instead sigma_s / rho, interpolated separately: vdb_render's density-weighted albedo (see
  density_weighted_albedo).
  No Principled Volume: its "Density Attribute" (default "density") multiplies the Density input,
  and its absorption term is (1 - C)(1 - sqrt(AbsorptionColor))*D; explicit nodes avoid both traps.
  Attribute nodes read volume grids by name as float4 (kernel/svm/attribute.h): Fac of a float grid
  is its value, Color of a Vec3S grid is its RGB, Color of a float grid is (v, v, v).
  Volume data are kept at full float precision (Volume.render.precision 'FULL'; Blender's default
  'HALF' would round densities), clipping 0 (no density is treated as empty), auto step size.
  Interpolation: Cycles only offers trilinear ('LINEAR', used here) or tricubic, vdb_render defaults
  to nearest: run vdb_render with --interp trilinear for the same medium.
* Voxel placement. The volume object has the identity transform, so the grid's own index-to-world
  transform places it. Caveat: Cycles' trilinear lookup (kernel/device/cpu/image.h,
  NanoVDBInterpolator::interp_3d_linear, and the dense path alike) subtracts 0.5 after the
  world-to-index transform, i.e. it puts voxel i's value at index i + 1/2, while OpenVDB and
  vdbappear put it at index i. --openvdb-voxel-centres translates the object by -M(1/2,1/2,1/2)
  (M = the density grid's index-to-object linear part) so that the two coincide.
* Environment: constant radiance R. World Background node colour (1,1,1) (or R,G,B with strength 1),
  strength R; the background closure weight is colour*strength and is the radiance seen along a ray.
  With neither --env nor --sun the medium gets vdb_render's default lights: --env 0.1 and
  --sun 0.51,0.65,-0.565,3 (libvdbappear/render/scene_description.h, defaultLights).
* Sun: DX,DY,DZ is the direction light travels, STRENGTH the irradiance on a plane facing it.
  Blender's sun energy is in W/m^2 (bpy.types.SunLight.energy) and, with angle 0, Cycles uses it
  unscaled (scene/light.cpp: invarea = 1 when the disc area is 0), so energy = STRENGTH. A light
  shines along its local -Z axis, which is rotated onto DX,DY,DZ.
* Camera: pinhole at --camera-pos looking at --camera-target, image up from --camera-up
  (right = forward x up, up' = right x forward, as libvdbappear/render/camera.cpp), vertical field
  of view --fov (sensor_fit 'VERTICAL', angle_y), no depth of field, clip range [1e-5, 1e6].
* Film: box pixel filter of width 1 px (uniform jitter within the pixel, like vdb_render's per-pixel
  jitter), no denoising, no adaptive sampling, no clamping, light threshold 0, no path guiding, no
  light tree, all bounce limits 1024, not transparent, exposure 1; view transform 'Standard', look
  'None', exposure 0, gamma 1 (EXR output is linear anyway).

Timing: "seconds" is the wall time of bpy.ops.render.render(), which includes Cycles' scene sync
(reading the grids, NanoVDB conversion, bounding mesh, BVH). To time path tracing alone, render at
two sample counts and take the difference (scripts/bench_render.py does). (A warm-up render with
persistent data does not work for this in 3.4: the second render returns at once with the first
render's image.)
"""

import argparse
import json
import math
import os
import struct
import sys
import time

import bpy
from mathutils import Matrix, Vector

UNSUPPORTED_PHASE = ("sggx_diag", "sggx_offdiag", "phase_table", "phase_id")


def fail(message):
    print("blender_scene.py: error: " + message, file=sys.stderr)
    sys.stderr.flush()
    sys.exit(2)


def note(message):
    print("blender_scene.py: " + message, file=sys.stderr)


# ----------------------------------------------------------------------------------------------------
# Command line


def floats(count_options):
    def parse(text):
        try:
            values = [float(v) for v in text.split(",")]
        except ValueError:
            raise argparse.ArgumentTypeError("'%s': expected comma-separated numbers" % text)
        if len(values) not in count_options:
            raise argparse.ArgumentTypeError(
                "'%s': expected %s values" % (text, " or ".join(str(c) for c in count_options)))
        if not all(math.isfinite(v) for v in values):
            raise argparse.ArgumentTypeError("'%s': values must be finite" % text)
        return values
    return parse


def resolution(text):
    parts = text.lower().split("x")
    try:
        if len(parts) == 1:
            w = h = int(parts[0])
        elif len(parts) == 2:
            w, h = int(parts[0]), int(parts[1])
        else:
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError("--res '%s': expected WxH or N" % text)
    if not (1 <= w <= 16384 and 1 <= h <= 16384):
        raise argparse.ArgumentTypeError("--res '%s': sizes must lie in 1..16384" % text)
    return w, h


def parse_args():
    raw = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    # Let vectors start with a minus sign without '=' (--sun -1,0,0,3): argparse would take
    # '-1,0,0,3' for an option.
    argv = []
    for token in raw:
        if argv and argv[-1].startswith("--") and "=" not in argv[-1] and len(token) > 1 \
                and token[0] == "-" and (token[1].isdigit() or token[1] == "."):
            argv[-1] += "=" + token
        else:
            argv.append(token)
    p = argparse.ArgumentParser(prog="blender_scene.py",
                                description="Render a vdbappear medium with Cycles on the CPU.")
    p.add_argument("--vdb", required=True, help="medium (OpenVDB file with a 'density' grid)")
    p.add_argument("--out", required=True, help="output OpenEXR file (linear, float32)")
    p.add_argument("--res", type=resolution, default=(256, 256), help="WxH or N (default 256)")
    p.add_argument("--spp", type=int, required=True, help="samples per pixel")
    p.add_argument("--camera-pos", type=floats((3,)), required=True)
    p.add_argument("--camera-target", type=floats((3,)), required=True)
    p.add_argument("--camera-up", type=floats((3,)), default=[0.0, 0.0, 1.0])
    p.add_argument("--fov", type=float, default=30.0, help="vertical field of view, degrees")
    p.add_argument("--env", type=floats((1, 3)), help="constant environment radiance R or R,G,B")
    p.add_argument("--sun", type=floats((4,)), help="DX,DY,DZ,STRENGTH (direction of travel; irradiance)")
    p.add_argument("--point-light", type=floats((4,)),
                   help="X,Y,Z,INTENSITY: an isotropic point light, irradiance INTENSITY / r^2 at distance r")
    p.add_argument("--ground-plane", type=floats((4,)),
                   help="CX,CY,Z,HALF: a diffuse square z = Z centred on (CX, CY), half-side HALF (vdb_render --ground)")
    p.add_argument("--ground-albedo", type=floats((1, 3)), default=[0.5], help="A or R,G,B (default 0.5)")
    p.add_argument("--threads", type=int, default=0, help="render threads (0: all cores)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--step-rate", type=float, default=1.0,
                   help="Cycles' volume step rate (default 1.0: one voxel per step; smaller is finer)")
    p.add_argument("--volume-bounces", type=int, default=1024,
                   help="Cycles' volume bounce limit (default 1024; 0: single scattering, "
                        "as vdb_render --max-depth 1)")
    p.add_argument("--openvdb-voxel-centres", action="store_true",
                   help="shift the object by half a voxel so voxel i's value sits at index i (OpenVDB)")
    p.add_argument("--blackbody", metavar="GRID[:KELVIN[:INTENSITY]]",
                   help="add Principled Volume's blackbody light of the float grid GRID (Temperature KELVIN, "
                        "default 1000; Blackbody Intensity INTENSITY, default 1), as vdb_render's "
                        "--grid emission=blackbody:GRID[:KELVIN[:INTENSITY]] (docs/medium.md 3b)")
    p.add_argument("--emission-grid", action="store_true",
                   help="add the medium's 'emission' grid (vec3) as light per unit length, an Emission shader "
                        "of strength 1 (the cycles convention of docs/medium.md 3b)")
    p.add_argument("--force", action="store_true",
                   help="render SGGX / tabulated / multi-lobe media with their HG or isotropic fallback")
    a = p.parse_args(argv)
    if a.spp < 1:
        p.error("--spp must be at least 1")
    if not (0 < a.fov < 180):
        p.error("--fov must lie in (0, 180) degrees")
    if a.volume_bounces < 0:
        p.error("--volume-bounces must be >= 0")
    if a.threads < 0:
        p.error("--threads must be >= 0")
    if a.env is not None and any(v < 0 for v in a.env):
        p.error("--env must be >= 0")
    return a


# ----------------------------------------------------------------------------------------------------
# File-level metadata of an OpenVDB file (Blender's Python API does not expose it). Layout, from
# openvdb/io/Archive.cc readHeader() and MetaMap::readMeta(): int64 magic 0x56444220, uint32 file
# version, [>= 211] uint32 library major + minor, [>= 212] char has-grid-offsets, [220..221] char
# is-compressed, [>= 218] 36-char ASCII UUID else 16 bytes; then uint32 count and per entry: name
# (uint32 length + bytes), type name (same), uint32 byte size + value bytes (little endian).


def read_vdb_file_metadata(path):
    out = {}
    with open(path, "rb") as f:
        def rd(n):
            b = f.read(n)
            if len(b) != n:
                raise ValueError("truncated VDB header")
            return b

        def u32():
            return struct.unpack("<I", rd(4))[0]

        def string():
            return rd(u32()).decode("utf-8", "replace")

        if struct.unpack("<q", rd(8))[0] != 0x56444220:
            raise ValueError("not a VDB file")
        version = u32()
        if version >= 211:
            rd(8)
        if version >= 212:
            rd(1)
        if 220 <= version < 222:
            rd(1)
        rd(36 if version >= 218 else 16)
        for _ in range(u32()):
            name, type_name = string(), string()
            data = rd(u32())
            if type_name == "float" and len(data) == 4:
                out[name] = struct.unpack("<f", data)[0]
            elif type_name == "double" and len(data) == 8:
                out[name] = struct.unpack("<d", data)[0]
            elif type_name == "int32" and len(data) == 4:
                out[name] = struct.unpack("<i", data)[0]
            else:
                out[name] = (type_name, len(data))
    return out


# ----------------------------------------------------------------------------------------------------
# Helpers


def set_if(owner, name, value, label):
    """Set owner.name = value when this Blender has it; say so on stderr when it does not."""
    if owner is not None and hasattr(owner, name):
        setattr(owner, name, value)
        return True
    note("%s.%s not in this Blender, left out" % (label, name))
    return False


def grid_matrix(grid):
    """Index-to-object 4x4 of a VolumeGrid, as a mathutils.Matrix acting on column vectors.
    Blender >= 3.5 returns a Matrix; 3.0-3.4 a 4x4 float array holding the columns."""
    m = grid.matrix_object
    if isinstance(m, Matrix):
        return m.copy()
    return Matrix([list(row) for row in m]).transposed()


# ----------------------------------------------------------------------------------------------------
# Scene


def clear_scene():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.lights, bpy.data.cameras, bpy.data.materials, bpy.data.volumes):
        for block in list(coll):
            if block.users == 0:
                coll.remove(block)


def load_volume(path):
    vol = bpy.data.volumes.new("medium")
    vol.filepath = path
    if not vol.grids.load():
        fail("%s: Blender cannot read it (%s)" % (path, vol.grids.error_message or "unknown error"))
    grids = {g.name: g for g in vol.grids}
    if "density" not in grids:
        fail("%s: no grid named 'density'" % path)
    if grids["density"].data_type != "FLOAT":
        fail("%s: grid 'density' is %s, expected FLOAT" % (path, grids["density"].data_type))
    # Full float precision (default 'HALF'), no clipping, object space, automatic step size.
    vol.render.precision = "FULL"
    vol.render.clipping = 0.0
    vol.render.space = "OBJECT"
    vol.render.step_size = 0.0
    return vol, grids


def attribute(nt, name):
    node = nt.nodes.new("ShaderNodeAttribute")
    node.attribute_type = "GEOMETRY"
    node.attribute_name = name
    return node


SIGMA_S_GRIDS = ("sigma_s_r", "sigma_s_g", "sigma_s_b")


def density_weighted_albedo(nt, density):
    """trilinear(rho * albedo) / trilinear(rho) per channel: the albedo vdb_render's trilinear lookup sees,
    from the separately interpolated float grids sigma_s_r, _g, _b and "density" (Cycles' vector divide
    gives 0 where rho = 0), used as a colour with density rho. Float grids, not one Vec3 grid: Cycles 3.4
    does not sample a Vec3 grid at the same points as a float grid (a Vec3 grid holding rho*(1,1,1)
    divided by "density" renders a white furnace at 1.14 with fireflies; float grids give 1)."""
    combine = nt.nodes.new("ShaderNodeCombineXYZ")
    for axis, name in zip("XYZ", SIGMA_S_GRIDS):
        nt.links.new(attribute(nt, name).outputs["Fac"], combine.inputs[axis])
    divide = nt.nodes.new("ShaderNodeVectorMath")
    divide.operation = "DIVIDE"
    nt.links.new(combine.outputs["Vector"], divide.inputs[0])
    nt.links.new(density.outputs["Color"], divide.inputs[1])  # Color of a float grid: (v, v, v)
    return divide.outputs["Vector"]


def blackbody_emission(nt, rule):
    """Principled Volume with Density 0: only its blackbody light, of the grid named in --blackbody
    (Cycles' svm principled volume adds it whatever the density, the cycles convention)."""
    parts = rule.split(":")
    pv = nt.nodes.new("ShaderNodeVolumePrincipled")
    pv.inputs["Density"].default_value = 0.0
    pv.inputs["Density Attribute"].default_value = ""
    pv.inputs["Temperature Attribute"].default_value = parts[0]
    pv.inputs["Temperature"].default_value = float(parts[1]) if len(parts) > 1 else 1000.0
    pv.inputs["Blackbody Intensity"].default_value = float(parts[2]) if len(parts) > 2 else 1.0
    return pv.outputs["Volume"]


def medium_material(grids, hg_g, blackbody=None, emission_grid=False):
    """Volume Scatter (colour albedo, density rho, anisotropy g) + Volume Absorption (colour albedo,
    density rho): sigma_s = albedo*rho, sigma_a = (1-albedo)*rho, sigma_t = rho (see module doc).
    With premultiplied grids sigma_s_r, _g, _b (scripts/premultiply_albedo.py) the albedo is
    density_weighted_albedo, so that sigma_s = trilinear(rho*albedo) as in vdb_render."""
    mat = bpy.data.materials.new("medium")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    out.target = "ALL"

    density = attribute(nt, "density")
    scatter = nt.nodes.new("ShaderNodeVolumeScatter")
    nt.links.new(density.outputs["Fac"], scatter.inputs["Density"])
    if "hg_g" in grids:
        nt.links.new(attribute(nt, "hg_g").outputs["Fac"], scatter.inputs["Anisotropy"])
    else:
        scatter.inputs["Anisotropy"].default_value = hg_g

    if all(name in grids for name in SIGMA_S_GRIDS):
        albedo = density_weighted_albedo(nt, density)
        note("albedo = sigma_s / density (density-weighted, as vdb_render's trilinear lookup)")
    elif "albedo" in grids:
        albedo = attribute(nt, "albedo").outputs["Color"]
    else:
        albedo = None
    if albedo is not None:
        absorb = nt.nodes.new("ShaderNodeVolumeAbsorption")
        nt.links.new(albedo, scatter.inputs["Color"])
        nt.links.new(albedo, absorb.inputs["Color"])
        nt.links.new(density.outputs["Fac"], absorb.inputs["Density"])
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(scatter.outputs["Volume"], add.inputs[0])
        nt.links.new(absorb.outputs["Volume"], add.inputs[1])
        shader = add.outputs["Shader"]
    else:
        # Albedo 1 everywhere: (1 - 1)*rho = 0 absorption, scattering only.
        scatter.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        shader = scatter.outputs["Volume"]
    lights = []
    if blackbody:
        lights.append(blackbody_emission(nt, blackbody))
    if emission_grid:
        emission = nt.nodes.new("ShaderNodeEmission")
        emission.inputs["Strength"].default_value = 1.0
        nt.links.new(attribute(nt, "emission").outputs["Color"], emission.inputs["Color"])
        lights.append(emission.outputs["Emission"])
    for light in lights:
        glow = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(shader, glow.inputs[0])
        nt.links.new(light, glow.inputs[1])
        shader = glow.outputs["Shader"]
    nt.links.new(shader, out.inputs["Volume"])
    # No surface shader: the bounding mesh Cycles builds around the voxels is fully transparent.

    cm = mat.cycles
    set_if(cm, "volume_interpolation", "LINEAR", "Material.cycles")
    set_if(cm, "homogeneous_volume", False, "Material.cycles")
    return mat


def add_camera(scene, a):
    pos, target, up = Vector(a.camera_pos), Vector(a.camera_target), Vector(a.camera_up)
    forward = target - pos
    if forward.length == 0:
        fail("--camera-pos and --camera-target coincide")
    forward.normalize()
    right = forward.cross(up)
    if right.length <= 1e-9 * max(up.length, 1e-300):
        fail("--camera-up is parallel to the view direction")
    right.normalize()
    true_up = right.cross(forward)
    # Blender cameras look along local -Z with local +Y up: columns (right, up, -forward).
    rot = Matrix((
        (right.x, true_up.x, -forward.x, pos.x),
        (right.y, true_up.y, -forward.y, pos.y),
        (right.z, true_up.z, -forward.z, pos.z),
        (0.0, 0.0, 0.0, 1.0),
    ))
    cam = bpy.data.cameras.new("camera")
    cam.type = "PERSP"
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(a.fov)
    cam.shift_x = cam.shift_y = 0.0
    cam.clip_start = 1e-5
    cam.clip_end = 1e6
    cam.dof.use_dof = False
    ob = bpy.data.objects.new("camera", cam)
    ob.matrix_world = rot
    scene.collection.objects.link(ob)
    scene.camera = ob


def add_world(scene, env):
    world = bpy.data.worlds.new("environment")
    world.use_nodes = True
    nt = world.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputWorld")
    bg = nt.nodes.new("ShaderNodeBackground")
    if len(env) == 1:
        bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        bg.inputs["Strength"].default_value = env[0]
    else:
        bg.inputs["Color"].default_value = (env[0], env[1], env[2], 1.0)
        bg.inputs["Strength"].default_value = 1.0
    nt.links.new(bg.outputs["Background"], out.inputs["Surface"])
    scene.world = world
    return world


def add_light(scene, kind, energy):
    """A white light of Blender type `kind` ("SUN", "POINT") that casts shadows through every bounce;
    returns its object, linked into the scene."""
    light = bpy.data.lights.new(kind.lower(), kind)
    light.energy = energy
    light.color = (1.0, 1.0, 1.0)
    label = kind.capitalize() + "Light"
    set_if(light, "use_shadow", True, label)
    set_if(light.cycles, "max_bounces", 1024, label + ".cycles")
    set_if(light.cycles, "cast_shadow", True, label + ".cycles")
    ob = bpy.data.objects.new(kind.lower(), light)
    scene.collection.objects.link(ob)
    return ob


def add_sun(scene, sun):
    d = Vector(sun[:3])
    if d.length == 0:
        fail("--sun: direction is zero")
    ob = add_light(scene, "SUN", sun[3])  # W/m^2 = irradiance on a plane facing the light
    ob.data.angle = 0.0                   # a delta (directional) light, as vdb_render's
    # A light shines along its local -Z: rotate -Z onto the direction of travel.
    ob.matrix_world = d.normalized().to_track_quat("-Z", "Y").to_matrix().to_4x4()


# Blender's point-light power P (W) for a radiant intensity of 1 W/sr: Cycles 3.4 gives a point light
# of zero radius the intensity P / (4 pi). Measured (docs/rendering.md §7): a diffuse ground of
# albedo 0.5, 3 below a point light of intensity 10, seen from straight above over a 4-degree field:
# Cycles 0.17566 with this factor, vdb_render 0.17567, a I cos / (pi r^2) at the centre 0.17684.
POINT_WATTS_PER_INTENSITY = 4 * math.pi


def add_point_light(scene, point):
    if not point[3] >= 0:
        fail("--point-light: the intensity must be >= 0")
    ob = add_light(scene, "POINT", point[3] * POINT_WATTS_PER_INTENSITY)
    ob.data.shadow_soft_size = 0.0  # a point, as vdb_render's
    ob.location = Vector(point[:3])


def add_ground(scene, plane, albedo):
    cx, cy, z, half = plane
    mesh = bpy.data.meshes.new("ground")
    mesh.from_pydata([(cx - half, cy - half, z), (cx + half, cy - half, z), (cx + half, cy + half, z),
                      (cx - half, cy + half, z)], [], [(0, 1, 2, 3)])
    mesh.update()
    material = bpy.data.materials.new("ground")
    material.use_nodes = True
    nt = material.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
    rgb = albedo * 3 if len(albedo) == 1 else albedo
    diffuse.inputs["Color"].default_value = (rgb[0], rgb[1], rgb[2], 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0  # Lambertian
    nt.links.new(diffuse.outputs["BSDF"], out.inputs["Surface"])
    mesh.materials.append(material)
    ob = bpy.data.objects.new("ground", mesh)
    scene.collection.objects.link(ob)


def configure_render(scene, a):
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y = a.res
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = False
    r.use_motion_blur = False
    r.use_border = False
    r.use_compositing = False
    r.use_sequencer = False
    r.use_persistent_data = False
    if a.threads > 0:
        r.threads_mode = "FIXED"
        r.threads = a.threads
    else:
        r.threads_mode = "AUTO"

    img = r.image_settings
    img.file_format = "OPEN_EXR"
    img.color_mode = "RGB"
    img.color_depth = "32"
    img.exr_codec = "ZIP"

    vs = scene.view_settings
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    vs.use_curve_mapping = False

    c = scene.cycles
    label = "Scene.cycles"
    c.device = "CPU"
    set_if(c, "feature_set", "SUPPORTED", label)
    c.samples = a.spp
    set_if(c, "use_adaptive_sampling", False, label)
    set_if(c, "use_denoising", False, label)
    set_if(c, "use_preview_denoising", False, label)
    set_if(c, "time_limit", 0.0, label)
    set_if(c, "use_guiding", False, label)
    set_if(c, "use_light_tree", False, label)            # 3.5+
    set_if(c, "light_sampling_threshold", 0.0, label)
    set_if(c, "sample_clamp_direct", 0.0, label)
    set_if(c, "sample_clamp_indirect", 0.0, label)
    set_if(c, "blur_glossy", 0.0, label)
    set_if(c, "caustics_reflective", True, label)
    set_if(c, "caustics_refractive", True, label)
    for name in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                 "volume_bounces", "transparent_max_bounces"):
        set_if(c, name, a.volume_bounces if name == "volume_bounces" else 1024, label)
    set_if(c, "min_light_bounces", 0, label)
    set_if(c, "min_transparent_bounces", 0, label)
    set_if(c, "ao_bounces_render", 0, label)
    set_if(c, "pixel_filter_type", "BOX", label)
    set_if(c, "filter_width", 1.0, label)
    set_if(c, "film_exposure", 1.0, label)
    set_if(c, "seed", a.seed % 2147483648, label)
    set_if(c, "use_animated_seed", False, label)
    set_if(c, "use_layer_samples", "IGNORE", label)
    # Volume step rate: Cycles' default 1.0 unless --step-rate (smaller: finer ray marching, less bias).
    set_if(c, "volume_step_rate", a.step_rate, label)
    set_if(c, "volume_max_steps", max(1024, int(1024 / a.step_rate)), label)
    for layer in scene.view_layers:
        set_if(layer, "use_volumes", True, "ViewLayer")
        if hasattr(layer, "cycles"):
            set_if(layer.cycles, "use_denoising", False, "ViewLayer.cycles")
            set_if(layer.cycles, "denoising_store_passes", False, "ViewLayer.cycles")


def main():
    a = parse_args()
    vdb = os.path.abspath(a.vdb)
    out = os.path.abspath(a.out)
    if not os.path.isfile(vdb):
        fail("%s: no such file" % a.vdb)
    try:
        meta = read_vdb_file_metadata(vdb)
    except (OSError, ValueError) as e:
        fail("%s: %s" % (a.vdb, e))

    scene = bpy.context.scene
    clear_scene()
    vol, grids = load_volume(vdb)

    lobes = sorted(n for n in grids if n.startswith("lobe") or n in UNSUPPORTED_PHASE)
    if lobes:
        msg = "%s: Cycles has only HG phase functions; grids %s cannot be honoured" % (a.vdb, ", ".join(lobes))
        if not a.force:
            fail(msg + " (--force renders the HG/isotropic fallback)")
        note("warning: " + msg + "; rendering the HG/isotropic fallback")

    hg_g = 0.0
    hg_source = "isotropic"
    if "hg_g" in grids:
        hg_source = "grid"
    elif isinstance(meta.get("hg_g"), float):
        hg_g = meta["hg_g"]
        hg_source = "metadata"
        if not (-1 < hg_g < 1):
            fail("%s: metadata 'hg_g' = %g outside (-1,1)" % (a.vdb, hg_g))

    ob = bpy.data.objects.new("medium", vol)
    scene.collection.objects.link(ob)
    ob.hide_render = False
    ob.hide_viewport = False
    ob.matrix_world = Matrix.Identity(4)
    if a.openvdb_voxel_centres:
        linear = grid_matrix(grids["density"]).to_3x3()
        ob.matrix_world = Matrix.Translation(-(linear @ Vector((0.5, 0.5, 0.5))))
    if a.blackbody and a.blackbody.split(":")[0] not in grids:
        fail("%s: --blackbody %s: no grid named '%s'" % (a.vdb, a.blackbody, a.blackbody.split(":")[0]))
    if a.emission_grid and "emission" not in grids:
        fail("%s: --emission-grid: no grid named 'emission'" % a.vdb)
    vol.materials.append(medium_material(grids, hg_g, a.blackbody, a.emission_grid))

    if a.env is None and a.sun is None and a.point_light is None:  # vdb_render's defaultLights()
        a.env, a.sun = [0.1], [0.51, 0.65, -0.565, 3.0]
    add_world(scene, a.env if a.env is not None else [0.0])
    if a.sun is not None:
        add_sun(scene, a.sun)
    if a.point_light is not None:
        add_point_light(scene, a.point_light)
    if a.ground_plane is not None:
        add_ground(scene, a.ground_plane, a.ground_albedo)
    add_camera(scene, a)
    configure_render(scene, a)

    t0 = time.perf_counter()
    result = bpy.ops.render.render(write_still=False)
    seconds = time.perf_counter() - t0
    if "FINISHED" not in result:
        fail("render did not finish (%s)" % ", ".join(result))

    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    bpy.data.images["Render Result"].save_render(filepath=out, scene=scene)
    if not os.path.isfile(out):
        fail("%s: not written" % a.out)

    report = {
        "seconds": seconds,
        "spp": a.spp,
        "resolution": list(a.res),
        "threads": a.threads,
        "seed": scene.cycles.seed,
        "phase": hg_source,
        "hg_g": hg_g if hg_source == "metadata" else (None if hg_source == "grid" else 0.0),
        "albedo_grid": "albedo" in grids,
        "blackbody": a.blackbody,
        "openvdb_voxel_centres": bool(a.openvdb_voxel_centres),
        "blender": bpy.app.version_string,
        "out": out,
    }
    sys.stdout.write(json.dumps(report) + "\n")
    sys.stdout.flush()


main()
