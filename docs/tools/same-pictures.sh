#!/bin/sh
# Renders every bench row (crates/bench/src/config.rs, in `relief render` flags)
# on several scenes and orientations with two relief binaries and compares
# the pictures byte for byte: a change that must not alter any picture is
# checked by `docs/tools/same-pictures.sh OLD_RELIEF NEW_RELIEF`.
#
# The scenes go beyond the bench's cube so that every geometry path runs:
# the shadow scene (shadow pass), the sphere and the plane (depth buffer,
# open surface seen from behind), model files (own materials, repeated
# triangles), the lines and points displays, tangent frames and tall
# sub-cell pixels. Prints one line per difference and a count; exits 1 if
# any picture differs.
set -u
old=${1:?usage: same-pictures.sh OLD_RELIEF NEW_RELIEF}
new=${2:?usage: same-pictures.sh OLD_RELIEF NEW_RELIEF}
root=$(cd "$(dirname "$0")/../.." && pwd)
models="$root/tests/data/models"
# A model file that names no material is drawn plain until a picture is
# named with it: the last two scenes name one ("+" joins a scene's words).
brick="$root/tests/data/reference-brick.png"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

# The bench rows, as flags (the reference setting is the default).
rows='
--threads-row-is-the-reference
--shading flat
--shading gouraud
--normals face
--texture off
--filter nearest
--filter nearest-mip
--filter trilinear
--filter anisotropic
--bump off
--specular on
--technique emboss
--technique dot3
--technique parallax
--technique pom
--height-derivative texel
--technique dot3 --light-vector vertex
--aa 2x2
--aa 4x4
--aa msaa4
--lights off
--shading flat --texture off --bump off
--shading gouraud --filter nearest --bump off
--technique emboss --filter trilinear
--technique dot3 --filter trilinear
--filter anisotropic --aa 4x4
--technique dot3 --normal-map '"$models"'/gltf/ClearCoatTest/RibsNormal.png
--tangent-frames
--environment on
--display lines
--display points
--specular on --shading gouraud
--tangent-frames --aa msaa4
'

scenes="
--scene=cube
--scene=shadow
--model=sphere
--model=plane
--model=$models/gltf/BoxTextured.glb
--model=$models/tinyobjloader/catmark_torus_creases0.obj
--model=$models/assimp/sphereWithHole.stl
--model=$models/tinyobjloader/catmark_torus_creases0.obj+$brick
--model=$models/assimp/sphereWithHole.stl+$brick
"

checked=0
differ=0
# The row list holds one row per line; a scene or rotation per word.
echo "$rows" | while IFS= read -r row; do
    [ -z "$row" ] && continue
    [ "$row" = "--threads-row-is-the-reference" ] && row=""
    for words in $scenes; do
        scene=$(echo "$words" | tr + ' ')
        for rotate in 0,0,0 25,-35,10 170,60,-20; do
            for size in "--width 96 --height 64" "--width 64 --height 48 --symbols octant"; do
                # shellcheck disable=SC2086
                "$old" render $row $scene --rotate=$rotate $size --out "$dir/old.ppm" 2>"$dir/old.err"
                a=$?
                # shellcheck disable=SC2086
                "$new" render $row $scene --rotate=$rotate $size --out "$dir/new.ppm" 2>"$dir/new.err"
                b=$?
                checked=$((checked + 1))
                if [ $a -ne $b ] || ! cmp -s "$dir/old.ppm" "$dir/new.ppm"; then
                    differ=$((differ + 1))
                    echo "DIFFERS: $row $scene --rotate=$rotate $size (exit $a / $b)"
                fi
                rm -f "$dir/old.ppm" "$dir/new.ppm"
            done
        done
    done
    echo "$checked $differ" >"$dir/count"
done
read -r checked differ <"$dir/count"
echo "$checked pictures compared, $differ differ"
[ "$differ" -eq 0 ]
