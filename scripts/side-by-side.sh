#!/usr/bin/env bash
# Places PNG images of the same size left to right, each with its label underneath, using
# ImageMagick's montage: at their own size, or scaled to TILE_WIDTH pixels wide when that
# environment variable is set (to keep images for docs small).
# Usage: [TILE_WIDTH=N] scripts/side-by-side.sh OUT.png|OUT.jpg LABEL=IMAGE.png [LABEL=IMAGE.png ...]
set -euo pipefail

usage() {
  echo "usage: $0 OUT.png LABEL=IMAGE.png [LABEL=IMAGE.png ...]" >&2
  [ $# -gt 0 ] && echo "error: $*" >&2
  exit 2
}

[ $# -ge 2 ] || usage "need an output file and at least one LABEL=IMAGE.png"
out=$1
shift
case "$out" in
  *.png) format=png ;;
  *.jpg) format=jpg ;;
  *) usage "the output '$out' must end in .png or .jpg" ;;
esac

labels=()
images=()
for arg in "$@"; do
  case "$arg" in
    ?*=?*) ;;
    *) usage "'$arg' is not LABEL=IMAGE.png" ;;
  esac
  label=${arg%%=*}
  image=${arg#*=}
  [ -f "$image" ] || usage "no such file: $image"
  [ -r "$image" ] || usage "cannot read $image"
  [ "$(head -c 8 "$image" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] ||
    usage "$image is not a PNG file"
  labels+=("$label")
  images+=("$image")
done

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
case "$(montage -version 2>/dev/null || true)" in
  *ImageMagick*) ;;
  *) bash "$script_dir/install-deps.sh" imagemagick ;;
esac

# A font montage can render the labels with: DejaVu Sans where there is one.
pick_font() {
  montage -list font 2>/dev/null | awk '
    $1 == "Font:" { if (!first) first = $2; if ($2 == "DejaVu-Sans") preferred = $2 }
    END { print (preferred ? preferred : first) }'
}
font=$(pick_font)
if [ -z "$font" ]; then
  bash "$script_dir/install-deps.sh" fonts-dejavu-core
  font=$(pick_font)
fi
[ -n "$font" ] || { echo "error: ImageMagick knows no font to write the labels with" >&2; exit 1; }

# The PNG's size from its IHDR chunk: width and height, big-endian, at bytes 16 to 23.
png_size() {
  local w h
  read -r w h < <(od -An -j16 -N8 -tu1 "$1" |
    awk '{ printf "%d %d\n", (($1 * 256 + $2) * 256 + $3) * 256 + $4,
                               (($5 * 256 + $6) * 256 + $7) * 256 + $8 }')
  echo "${w}x${h}"
}

size=$(png_size "${images[0]}")
for image in "${images[@]}"; do
  this=$(png_size "$image")
  [ "$this" = "$size" ] || usage "$image is $this but ${images[0]} is $size: the images must be the same size"
done

# montage reads escapes (%w, \n) and @FILE in a label; pass the label through literally.
literal_label() {
  local s=${1//\\/\\\\}
  s=${s//%/%%}
  [ "${s:0:1}" = "@" ] && s="\\$s"
  printf '%s' "$s"
}

args=()
for i in "${!images[@]}"; do
  args+=(-label "$(literal_label "${labels[$i]}")" "png:${images[$i]}")
done

mkdir -p "$(dirname "$out")"
geometry=+6+6
[ -n "${TILE_WIDTH:-}" ] && geometry="${TILE_WIDTH}x+6+6"
montage "${args[@]}" -tile "${#images[@]}x1" -geometry "$geometry" -background white -fill black \
  -font "$font" -pointsize 16 -quality 90 "$format:$out"
echo "image: $out"
