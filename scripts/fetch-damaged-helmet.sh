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

# Every file DamagedHelmet.gltf references (its one buffer and five images).
files="DamagedHelmet.gltf DamagedHelmet.bin
Default_albedo.jpg Default_metalRoughness.jpg Default_emissive.jpg Default_AO.jpg Default_normal.jpg"

source "$(dirname "$0")/khronos-sample.sh"
fetch_khronos_sample_main DamagedHelmet "${XDG_CACHE_HOME:-$HOME/.cache}/smlt/damaged-helmet" "$files" "$@"
