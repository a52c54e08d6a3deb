#!/usr/bin/env bash
# Downloads the Khronos glTF sample "Flight Helmet" (glTF-Sample-Assets, Models/FlightHelmet/glTF):
# FlightHelmet.gltf, FlightHelmet.bin (3,227,148 bytes) and the 15 PNG textures it references
# (2048x2048, the three LensesMat ones 1024x1024), plus the model's LICENSE.md and README.md.
# Roughly 45-50 MB (the three LeatherPartsMat PNGs are over 4 MiB each).
#
# Licence: per Khronos' Models/FlightHelmet/LICENSE.md and README.md the model files (text, images,
# binary) are CC0 1.0 Universal (SPDX CC0-1.0, https://creativecommons.org/publicdomain/zero/1.0/legalcode;
# README: "(c) 2018, Public. CC0 1.0 Universal", Gary Hsu for conversion from Maya). Khronos'
# metadata files (LICENSE.md, README.md, metadata.json) are CC BY 4.0. See LICENSE.md once fetched.
#
# Nothing this script fetches is committed to smlt: it goes to a cache folder.
# Usage: scripts/fetch-flight-helmet.sh [--from DIR] [DEST]
#   (default DEST: ${XDG_CACHE_HOME:-$HOME/.cache}/smlt/flight-helmet)
#   --from DIR copies from a local copy instead of downloading: DIR in Khronos' layout
#   (DIR/LICENSE.md, DIR/glTF/FlightHelmet.gltf, ...) or with every file directly in DIR.
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
dest=${1:-${XDG_CACHE_HOME:-$HOME/.cache}/smlt/flight-helmet}
base=https://raw.githubusercontent.com/KhronosGroup/glTF-Sample-Assets/main/Models/FlightHelmet

# Every file FlightHelmet.gltf references (its one buffer and fifteen images).
files="FlightHelmet.gltf FlightHelmet.bin
FlightHelmet_Materials_RubberWoodMat_BaseColor.png FlightHelmet_Materials_RubberWoodMat_Normal.png
FlightHelmet_Materials_RubberWoodMat_OcclusionRoughMetal.png
FlightHelmet_Materials_GlassPlasticMat_BaseColor.png FlightHelmet_Materials_GlassPlasticMat_Normal.png
FlightHelmet_Materials_GlassPlasticMat_OcclusionRoughMetal.png
FlightHelmet_Materials_MetalPartsMat_BaseColor.png FlightHelmet_Materials_MetalPartsMat_Normal.png
FlightHelmet_Materials_MetalPartsMat_OcclusionRoughMetal.png
FlightHelmet_Materials_LeatherPartsMat_BaseColor.png FlightHelmet_Materials_LeatherPartsMat_Normal.png
FlightHelmet_Materials_LeatherPartsMat_OcclusionRoughMetal.png
FlightHelmet_Materials_LensesMat_BaseColor.png FlightHelmet_Materials_LensesMat_Normal.png
FlightHelmet_Materials_LensesMat_OcclusionRoughMetal.png"

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
echo "fetching Khronos FlightHelmet from ${from:-$base} into $dest"
for f in LICENSE.md README.md; do
    get "" "$f"
done
for f in $files; do
    get glTF/ "$f"
done

# The buffer's length must match the byteLength that FlightHelmet.gltf declares.
want=$(tr -d ' \t\r\n' < "$dest/FlightHelmet.gltf" | grep -o '"buffers":\[{[^]]*' | grep -o '"byteLength":[0-9]*' | cut -d: -f2)
have=$(wc -c < "$dest/FlightHelmet.bin" | tr -d ' ')
if [ "$want" != "$have" ]; then
    echo "error: FlightHelmet.bin is $have bytes, FlightHelmet.gltf says $want (Git LFS pointer or truncated download?)" >&2
    exit 1
fi
# Images must be real PNG bytes (89 50 4E 47), not Git LFS pointers or error pages.
for f in $files; do
    case $f in *.png)
        if [ "$(head -c 4 "$dest/$f" | od -An -tx1 | tr -d ' \n')" != 89504e47 ]; then
            echo "error: $f is not a PNG (Git LFS pointer or error page?)" >&2
            exit 1
        fi ;;
    esac
done
echo "ok: $(echo $files | wc -w) files, FlightHelmet.bin $have bytes, in $dest"
