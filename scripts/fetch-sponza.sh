#!/usr/bin/env bash
# Downloads the Khronos glTF sample "Sponza" (glTF-Sample-Assets, Models/Sponza/glTF):
# Sponza.gltf, Sponza.bin (9,528,220 bytes) and the 69 JPEG/PNG textures it references,
# plus the model's LICENSE.md and README.md. About 42 MB.
#
# Licence: per Khronos' Models/Sponza/LICENSE.md the model files (text, images, binary)
# are under the "Cryengine Limited License Agreement" (SPDX LicenseRef-CRYENGINE-Agreement,
# https://www.cryengine.com/ce-terms); only Khronos' metadata files are CC BY 4.0.
# Credits: Crytek / Frank Meinl (Sponza, 2010), after Marko Dabrovic's original;
# fixes by Morgan McGuire; PBR textures by Alexandre Pestana. See README.md once fetched.
#
# Nothing this script fetches is committed to smlt: it goes to a cache folder.
# Usage: scripts/fetch-sponza.sh [DEST]   (default: ${XDG_CACHE_HOME:-$HOME/.cache}/smlt/sponza-khronos)
set -euo pipefail

dest=${1:-${XDG_CACHE_HOME:-$HOME/.cache}/smlt/sponza-khronos}
base=https://raw.githubusercontent.com/KhronosGroup/glTF-Sample-Assets/main/Models/Sponza

files="Sponza.gltf Sponza.bin
8773302468495022225.jpg 5061699253647017043.png 11872827283454512094.jpg 12501374198249454378.jpg
8006627369776289000.png 715093869573992647.jpg 4477655471536070370.jpg 7268504077753552595.jpg
8503262930880235456.jpg 13982482287905699490.jpg 8750083169368950601.jpg 16885566240357350108.jpg
16299174074766089871.jpg 5792855332885324923.jpg 11968150294050148237.jpg 2051777328469649772.jpg
14650633544276105767.jpg 4871783166746854860.jpg 10388182081421875623.jpg 15295713303328085182.jpg
9916269861720640319.jpg 15722799267630235092.jpg 6047387724914829168.jpg 8051790464816141987.jpg
14267839433702832875.jpg 5823059166183034438.jpg 13824894030729245199.jpg 6667038893015345571.jpg
7441062115984513793.jpg 8114461559286000061.jpg 3628158980083700836.jpg 11490520546946913238.jpg
3455394979645218238.jpg 7645212358685992005.jpg 6151467286084645207.jpg 8783994986360286082.jpg
2299742237651021498.jpg 4975155472559461469.jpg 3371964815757888145.jpg 7056944414013900257.jpg
4675343432951571524.jpg 7815564343179553343.jpg 2374361008830720677.jpg 2775690330959970771.jpg
332936164838540657.jpg 2185409758123873465.jpg 6593109234861095314.jpg 17876391417123941155.jpg
466164707995436622.jpg 4601176305987539675.jpg 11474523244911310074.jpg 4910669866631290573.jpg
9288698199695299068.jpg 14170708867020035030.jpg 16275776544635328252.png 1219024358953944284.jpg
3827035219084910048.jpg 755318871556304029.jpg 2411100444841994089.jpg 10381718147657362067.jpg
8481240838833932244.jpg 17556969131407844942.jpg 759203620573749278.jpg 6772804448157695701.jpg
13196865903111448057.jpg 14118779221266351425.jpg 2969916736137545357.jpg 8747919177698443163.jpg
white.png"

mkdir -p "$dest"
echo "fetching Khronos Sponza into $dest"
for f in LICENSE.md README.md; do
    curl -fsSL --retry 3 -o "$dest/$f" "$base/$f"
done
for f in $files; do
    curl -fsSL --retry 3 -o "$dest/$f" "$base/glTF/$f"
done

# The buffer's length must match the byteLength that Sponza.gltf declares.
want=$(tr -d ' \t\r\n' < "$dest/Sponza.gltf" | grep -o '"buffers":\[{[^]]*' | grep -o '"byteLength":[0-9]*' | cut -d: -f2)
have=$(wc -c < "$dest/Sponza.bin" | tr -d ' ')
if [ "$want" != "$have" ]; then
    echo "error: Sponza.bin is $have bytes, Sponza.gltf says $want (Git LFS pointer or truncated download?)" >&2
    exit 1
fi
# Images must be real image bytes, not Git LFS pointers.
for f in $files; do
    case $f in *.jpg|*.png)
        if head -c 40 "$dest/$f" | grep -q 'git-lfs'; then
            echo "error: $f is a Git LFS pointer, not an image" >&2
            exit 1
        fi ;;
    esac
done
echo "ok: $(echo $files | wc -w) files, Sponza.bin $have bytes, in $dest"
