#!/usr/bin/env bash
# Rebuilds the pictures of README's *Gallery* into docs/gallery/: `demkit map --render` of
# meshes demkit generates itself and of the papers' meshes.
#
#   docs/gallery.sh                 # builds demkit (release), then draws every picture
#   DEMKIT=path/to/demkit docs/gallery.sh    # uses that binary instead of building
#
# The papers' meshes are read from $DEMKIT_DATA (default: ../shared/data next to the
# repository); pictures whose mesh is missing are skipped with a message and the script ends
# with exit 1. SIZE (default 512) is the height of each panel in pixels.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
data="${DEMKIT_DATA:-$root/../shared/data}"
out="$root/docs/gallery"
size="${SIZE:-512}"
demkit="${DEMKIT:-}"
if [ -z "$demkit" ]; then
    cargo build --release --quiet -p demkit-cli --manifest-path "$root/Cargo.toml"
    demkit="${CARGO_TARGET_DIR:-$root/target}/release/demkit"
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
skipped=0

# picture NAME MESH [map options...]: maps MESH and draws docs/gallery/NAME.png. A map that
# stops at --max-iter (exit 3) is still drawn, with a note; any other failure stops the script.
picture() {
    local name="$1" mesh="$2"
    shift 2
    if [ ! -f "$mesh" ]; then
        echo "skipped $name: no $mesh (set DEMKIT_DATA)" >&2
        skipped=1
        return
    fi
    local start status=0
    start=$(date +%s.%N)
    "$demkit" map "$mesh" --out "$tmp/$name.mapped.obj" --render "$out/$name.png" --size "$size" \
        --report "$tmp/$name.json" --quiet "$@" || status=$?
    if [ "$status" -ne 0 ] && [ "$status" -ne 3 ]; then
        echo "error: demkit map failed on $mesh (exit $status)" >&2
        exit "$status"
    fi
    printf '%-22s %6.1f s  %s%s\n' "$name.png" "$(echo "$(date +%s.%N) - $start" | bc)" \
        "$(basename "$mesh")" "$([ "$status" -eq 3 ] && echo ' (not converged)')"
}

generate() {
    "$demkit" generate "$@" --quiet 2>/dev/null || "$demkit" generate "$@"
}

# Disks (DEM): a real face by area, a generated disk with a bump of population.
picture disk-face "$data/open/human_face.obj"
generate polygon --sides 6 --rings 40 --out "$tmp/disk.obj" >/dev/null
picture disk-lens "$tmp/disk.obj" --population "area*(1+4*exp(-8*((x-0.3)^2+(y-0.2)^2)))"

# Spheres (SDEM): a head by area, a generated sphere with a population rising along z.
picture sphere-maxplanck "$data/genus0/maxplanck.obj"
generate icosphere --subdivisions 4 --out "$tmp/sphere.obj" >/dev/null
picture sphere-gradient "$tmp/sphere.obj" --population "area*(1+4.5*(z+1))"

# Ellipsoids (EDEM): a hippocampus by area on the paper's ellipsoid 1:1:2.2, against the
# sphere (SDEM) that it is forced onto otherwise.
picture hippocampus-ellipsoid "$data/ellipsoidal/hippocampus.obj" --method edem --ellipsoid 1:1:2.2
picture hippocampus-sphere "$data/ellipsoidal/hippocampus.obj" --method sdem

# Surfaces with holes (DEQ): a generated disk with two holes, population doubled on x > 0.
generate disk-holes --hole 0.35:0.1:0.2 --hole -0.3:-0.2:0.15 --out "$tmp/holes.obj" >/dev/null
picture holes "$tmp/holes.obj" --population "area*(1+(x>0))"

# Tori (TDEM): the TDEM paper's Fig. 5 population on a generated torus.
generate torus --R 3 --r 1 --out "$tmp/torus.obj" >/dev/null
picture torus "$tmp/torus.obj" --torus 3:1 --population "area*(2-cos(atan2(y,x)))"

ls -l "$out"/*.png
exit "$skipped"
