#!/bin/sh
# Fails when a scene tools/pack_scene makes differs from the one in scenes/.
# Usage: packed_scenes_up_to_date.sh PACK_SCENE SOURCE_DIR WORK_DIR
set -e
pack_scene=$1 source=$2 work=$3
for job in "draco cornell cornell-draco" "webp textures textures-webp"; do
    set -- $job
    "$pack_scene" "--$1" "$source/scenes/$2.gltf" "$work/$3.glb"
    cmp "$source/scenes/$3.glb" "$work/$3.glb" || {
        echo "scenes/$3.glb is out of date: build/pack_scene --$1 scenes/$2.gltf scenes/$3.glb"
        exit 1
    }
done
echo "up to date: cornell-draco.glb, textures-webp.glb"
