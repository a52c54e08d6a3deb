#!/usr/bin/env bash
# Downloads the Khronos glTF sample "Damaged Helmet" (glTF-Sample-Assets, Models/DamagedHelmet/glTF):
# DamagedHelmet.gltf, DamagedHelmet.bin (558,504 bytes) and the five 2048x2048 JPEG textures it
# references, plus the model's LICENSE.md and README.md. About 3.8 MB.
#
# Licence: per Khronos' Models/DamagedHelmet/LICENSE.md and README.md the model files (text, images,
# binary) carry two licences: CC BY 4.0 International (SPDX CC-BY-4.0, (c) 2018 ctxwing, rebuild and
# conversion to glTF, https://creativecommons.org/licenses/by/4.0/legalcode) and CC BY-NC 4.0
# International (SPDX CC-BY-NC-4.0, (c) 2016 theblueturtle_, "Battle Damaged Sci-fi Helmet - PBR",
# https://sketchfab.com/models/b81008d513954189a063ff901f7abfe4,
# https://creativecommons.org/licenses/by-nc/4.0/legalcode). NonCommercial: attribute both, and do
# not use it commercially. Khronos' metadata files are CC BY 4.0. See LICENSE.md once fetched.
#
# Nothing this script fetches is committed to smlt: it goes to a cache folder.
# Usage: scripts/fetch-damaged-helmet.sh [--from DIR] [DEST]
#   (default DEST: ${XDG_CACHE_HOME:-$HOME/.cache}/smlt/damaged-helmet)
#   --from DIR copies from a local copy instead of downloading: DIR in Khronos' layout
#   (DIR/LICENSE.md, DIR/glTF/DamagedHelmet.gltf, ...) or with every file directly in DIR.
set -euo pipefail

from=
if [ "${1:-}" = --from ]; then
    if [ $# -lt 2 ]; then
        echo "usage: $0 [--from DIR] [DEST]" >&2
        exit 2
    fi
    from=$2
    shift 2
fi
dest=${1:-${XDG_CACHE_HOME:-$HOME/.cache}/smlt/damaged-helmet}
base=https://raw.githubusercontent.com/KhronosGroup/glTF-Sample-Assets/main/Models/DamagedHelmet

# Every file DamagedHelmet.gltf references (its one buffer and five images).
files="DamagedHelmet.gltf DamagedHelmet.bin
Default_albedo.jpg Default_metalRoughness.jpg Default_emissive.jpg Default_AO.jpg Default_normal.jpg"

# get SUBDIR FILE: SUBDIR is "" (the model's folder) or "glTF/".
get() {
    if [ -n "$from" ]; then
        if [ -f "$from/$1$2" ]; then
            cp "$from/$1$2" "$dest/$2"
        else
            cp "$from/$2" "$dest/$2"
        fi
    else
        curl -fsSL --retry 3 --retry-delay 2 -o "$dest/$2" "$base/$1$2"
    fi
}

mkdir -p "$dest"
echo "fetching Khronos DamagedHelmet from ${from:-$base} into $dest"
for f in LICENSE.md README.md; do
    get "" "$f"
done
for f in $files; do
    get glTF/ "$f"
done

# The buffer's length must match the byteLength that DamagedHelmet.gltf declares.
want=$(tr -d ' \t\r\n' < "$dest/DamagedHelmet.gltf" | grep -o '"buffers":\[{[^]]*' | grep -o '"byteLength":[0-9]*' | cut -d: -f2)
have=$(wc -c < "$dest/DamagedHelmet.bin" | tr -d ' ')
if [ "$want" != "$have" ]; then
    echo "error: DamagedHelmet.bin is $have bytes, DamagedHelmet.gltf says $want (Git LFS pointer or truncated download?)" >&2
    exit 1
fi
# Images must be real JPEG bytes (FF D8 FF), not Git LFS pointers or error pages.
for f in $files; do
    case $f in *.jpg)
        if [ "$(head -c 3 "$dest/$f" | od -An -tx1 | tr -d ' \n')" != ffd8ff ]; then
            echo "error: $f is not a JPEG (Git LFS pointer or error page?)" >&2
            exit 1
        fi ;;
    esac
done
echo "ok: $(echo $files | wc -w) files, DamagedHelmet.bin $have bytes, in $dest"
