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

source "$(dirname "$0")/khronos-sample.sh"
fetch_khronos_sample_main FlightHelmet "${XDG_CACHE_HOME:-$HOME/.cache}/smlt/flight-helmet" "$files" "$@"
