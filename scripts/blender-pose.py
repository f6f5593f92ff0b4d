"""Poses a glTF file in Blender and writes the evaluated meshes' world-space vertices.

An independent evaluation of glTF animation (node channels, skins, morph targets) for
tests/it/animation_playback.rs: Blender's own glTF importer reads the file, `frame_set` poses
it at each time, and the evaluated meshes (armature and shape keys applied) are written in
glTF's axes (+Y up), one list of vertices per time.

    blender -b --factory-startup --python-exit-code 1 -P scripts/blender-pose.py -- MODEL OUT.json [--animation N] T...

T: times in seconds (frame = T × the scene's frame rate, fractional frames as subframes).
--animation N: the file's animation N (0 by default) plays alone.
Output: {"fps": F, "poses": [{"time": T, "vertices": [[x, y, z], ...]}, ...]}.
"""

import json
import math
import os
import shutil
import struct
import sys
import tempfile
import urllib.parse

import bpy
import numpy

# Debian 12's Blender 3.4 importer still spells numpy's removed alias `np.bool` (numpy 1.24
# dropped it): give it back the builtin it stood for.
if not hasattr(numpy, "bool"):
    numpy.bool = bool


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) < 3:
        sys.exit("usage: blender -b -P blender-pose.py -- MODEL OUT.json [--animation N] T...")
    model, out, rest = argv[0], argv[1], argv[2:]
    animation = 0
    if rest and rest[0] == "--animation":
        animation = int(rest[1])
        rest = rest[2:]
    return model, out, animation, [float(t) for t in rest]


def read_gltf(model):
    """The file's JSON document, and its GLB binary chunk (None for .gltf)."""
    with open(model, "rb") as f:
        data = f.read()
    if data[:4] != b"glTF":
        return json.loads(data), None
    length = struct.unpack("<I", data[12:16])[0]
    return json.loads(data[20:20 + length]), data[20 + length:]


def with_first(model, index, folder):
    """A copy of `model` in `folder` whose animation `index` comes first.

    Blender's importer makes the first animation active and evaluates it once while importing:
    the properties it sets then stay set under any other action, where the file's rest pose
    should show. With the chosen animation first, what it sets is what every frame sets again.
    Relative buffer and image URIs are made absolute, so the copy reads the same files."""
    doc, binary = read_gltf(model)
    animations = doc.get("animations", [])
    animations.insert(0, animations.pop(index))
    base = os.path.dirname(os.path.abspath(model))
    for item in doc.get("buffers", []) + doc.get("images", []):
        uri = item.get("uri")
        if uri and not uri.startswith("data:"):
            item["uri"] = os.path.join(base, urllib.parse.unquote(uri))
    text = json.dumps(doc).encode()
    out = os.path.join(folder, "first" + (".glb" if binary is not None else ".gltf"))
    with open(out, "wb") as f:
        if binary is None:
            f.write(text)
        else:
            text += b" " * (-len(text) % 4)
            f.write(struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(text) + len(binary)))
            f.write(struct.pack("<I4s", len(text), b"JSON") + text + binary)
    return out


def play_first(model):
    """Plays the file's first animation alone: every object and shape-key set takes the action
    of its NLA track of that animation (the importer stashes each animation in tracks named
    after it: its name, else Anim_N), or none, and the tracks are muted."""
    doc, _ = read_gltf(model)
    animations = doc.get("animations", [])
    if not animations:
        return
    wanted = animations[0].get("name") or "Anim_0"
    for ids in (bpy.data.objects, bpy.data.shape_keys):
        for owner in ids:
            ad = owner.animation_data
            if ad is None:
                continue
            action = None
            for track in ad.nla_tracks:
                track.mute = True
                if track.name == wanted and track.strips:
                    action = track.strips[0].action
            ad.action = action


def main():
    model, out, animation, times = arguments()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    folder = tempfile.mkdtemp()
    if animation != 0:
        model = with_first(model, animation, folder)
    if "FINISHED" not in bpy.ops.import_scene.gltf(filepath=model):
        sys.exit(f"blender could not import {model}")
    play_first(model)
    scene = bpy.context.scene
    fps = scene.render.fps / scene.render.fps_base
    poses = []
    for t in times:
        frame = t * fps
        whole = math.floor(frame)
        scene.frame_set(int(whole), subframe=frame - whole)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        vertices = []
        for obj in scene.objects:
            if obj.type != "MESH":
                continue
            evaluated = obj.evaluated_get(depsgraph)
            mesh = evaluated.to_mesh()
            m = evaluated.matrix_world
            for v in mesh.vertices:
                w = m @ v.co
                # Blender's +Z up back to glTF's +Y up: (x, y, z) -> (x, z, -y).
                vertices.append([w.x, w.z, -w.y])
            evaluated.to_mesh_clear()
        poses.append({"time": t, "vertices": vertices})
    with open(out, "w") as f:
        json.dump({"fps": fps, "poses": poses}, f)
    shutil.rmtree(folder)


main()
