# A library for the fetch scripts of Khronos' glTF samples (sourced, not run): copies or
# downloads one model of KhronosGroup/glTF-Sample-Assets into a cache folder and checks what
# arrived. Nothing it fetches is committed to smlt.
#
#   fetch_khronos_sample_main MODEL DEFAULT_DEST FILES "$@"   (a fetch script's arguments:
#                                                             [--from DIR] [DEST])
#   fetch_khronos_sample MODEL DEST FROM FILES
#
# MODEL: the folder under Models/ (e.g. FlightHelmet), whose glTF is glTF/MODEL.gltf with one
# buffer MODEL.bin; DEST: the cache folder; FROM: "" to download, or a local copy in Khronos'
# layout (FROM/LICENSE.md, FROM/glTF/MODEL.gltf, ...) or with every file directly in it; FILES:
# the model's files under glTF/, whitespace-separated. LICENSE.md and README.md come too. The
# buffer's length must match the byteLength MODEL.gltf declares, and every .png and .jpg must
# begin with its format's signature (a Git LFS pointer or an error page does not).

fetch_khronos_sample() {
    local model=$1 dest=$2 from=$3 files=$4
    local base=https://raw.githubusercontent.com/KhronosGroup/glTF-Sample-Assets/main/Models/$model
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
    echo "fetching Khronos $model from ${from:-$base} into $dest"
    local f
    for f in LICENSE.md README.md; do
        get "" "$f"
    done
    for f in $files; do
        get glTF/ "$f"
    done
    local want have
    want=$(tr -d ' \t\r\n' < "$dest/$model.gltf" | grep -o '"buffers":\[{[^]]*' | grep -o '"byteLength":[0-9]*' | cut -d: -f2)
    have=$(wc -c < "$dest/$model.bin" | tr -d ' ')
    if [ "$want" != "$have" ]; then
        echo "error: $model.bin is $have bytes, $model.gltf says $want (Git LFS pointer or truncated download?)" >&2
        return 1
    fi
    local magic
    for f in $files; do
        case $f in
            *.png) magic=89504e47 ;;
            *.jpg | *.jpeg) magic=ffd8ff ;;
            *) continue ;;
        esac
        if [ "$(head -c $((${#magic} / 2)) "$dest/$f" | od -An -tx1 | tr -d ' \n')" != "$magic" ]; then
            echo "error: $f is not the image its name says (Git LFS pointer or error page?)" >&2
            return 1
        fi
    done
    echo "ok: $(echo $files | wc -w) files, $model.bin $have bytes, in $dest"
}

# A fetch script's whole work: its arguments [--from DIR] [DEST] (DEST by default
# DEFAULT_DEST), then fetch_khronos_sample.
fetch_khronos_sample_main() {
    local model=$1 dest=$2 files=$3 from=
    shift 3
    if [ "${1:-}" = --from ]; then
        if [ $# -lt 2 ]; then
            echo "usage: $0 [--from DIR] [DEST]" >&2
            exit 2
        fi
        from=$2
        shift 2
    fi
    fetch_khronos_sample "$model" "${1:-$dest}" "$from" "$files"
}
