#!/usr/bin/env bash
# Side-by-side run of demkit's EDEM/EDEQ and the authors' ellipsoidal MATLAB code (run under GNU
# Octave) on the same meshes: time, iterations, density variance, mean |mu|, radii and energy of
# each, as a markdown table on stdout. See bench/reference/README.md.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
# shellcheck source=bench/reference/lib.sh
. "$here/lib.sh"

usage() {
  cat <<EOF
Usage: bench/reference/compare_ellipsoid.sh [options] [CASE...]

  --edem DIR     the authors' code (github.com/garyptchoi/ellipsoidal-density-equalizing-map):
                 a checkout, or a git directory whose HEAD is exported [env DEMKIT_REF_EDEM]
  --data DIR     the real meshes (ellipsoidal/, genus0/)
                 [env DEMKIT_DATA, default ../shared/data beside the checkout]
  --demkit BIN   the demkit binary [target/release/demkit; built if missing]
  --timeout S    time limit of each run, in seconds [3000]
  --work DIR     where exports, outputs and logs go [a new temporary directory, kept]

CASE: edem:NAME or edeq:NAME. EDEM: ellipsoid1 ellipsoid2 ellipsoid3 ellipsoid_cts
ellipsoid_discts sphere (their own radii and population; the surface is its own initial map),
david1 (1:1.2:1.4), buddha (1:1:1.4), hippocampus (1:1:2.2), twistedball (1:0.8:1.4), by area.
EDEQ: the six NAME_edeq examples with their guesses, duck (1:1:1.2), hippocampus (1:1:1.5),
vaselion (1:1:1.4). Default: all of them.
EOF
}

edem_src=${DEMKIT_REF_EDEM:-}
data=${DEMKIT_DATA:-$root/../shared/data}
demkit=""
limit=3000
work=""
cases=()
while [ $# -gt 0 ]; do
  case $1 in
    --edem) edem_src=$2; shift 2 ;;
    --data) data=$2; shift 2 ;;
    --demkit) demkit=$2; shift 2 ;;
    --timeout) limit=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) usage >&2; die "unknown option $1" ;;
    *) cases+=("$1"); shift ;;
  esac
done
examples="ellipsoid1 ellipsoid2 ellipsoid3 ellipsoid_cts ellipsoid_discts sphere"
if [ ${#cases[@]} = 0 ]; then
  for n in $examples david1 buddha hippocampus twistedball; do cases+=("edem:$n"); done
  for n in $examples; do cases+=("edeq:${n}_edeq"); done
  cases+=(edeq:duck edeq:hippocampus edeq:vaselion)
fi

command -v octave-cli >/dev/null || die "octave-cli not found (apt-get install octave)"
[ -d "$data/ellipsoidal" ] || die "no meshes in $data (give --data or DEMKIT_DATA)"
data=$(cd "$data" && pwd)
if [ -z "$demkit" ]; then
  demkit=$root/target/release/demkit
  if [ ! -x "$demkit" ]; then
    say "building demkit (release) ..."
    (cd "$root" && cargo build --release --bin demkit) >&2
  fi
fi
[ -x "$demkit" ] || die "no demkit binary at $demkit"
[ -n "$work" ] || work=$(mktemp -d "${TMPDIR:-/tmp}/demkit-reference.XXXXXX")
mkdir -p "$work"
work=$(cd "$work" && pwd)
code=$(code_dir "$edem_src" edem)

E=$data/ellipsoidal; G=$data/genus0
radii_file() { tr -s ' \n' '::' <"$1" | sed 's/:*$//'; }
# mesh, population and radii (EDEM) or guess (EDEQ) of a case; self = 1 when the surface lies
# on the ellipsoid already (the authors' demos then start from it).
setup() { # KIND NAME
  pop=area; self=0
  case $1:$2 in
    edem:david1) mesh=$G/david1.obj; radii=1:1.2:1.4 ;;
    edem:twistedball) mesh=$G/twistedball.obj; radii=1:0.8:1.4 ;;
    edem:buddha) mesh=$E/buddha.obj; radii=1:1:1.4 ;;
    edem:hippocampus) mesh=$E/hippocampus.obj; radii=1:1:2.2 ;;
    edeq:duck) mesh=$G/duck.obj; radii=1:1:1.2 ;;
    edeq:hippocampus) mesh=$E/hippocampus.obj; radii=1:1:1.5 ;;
    edeq:vaselion) mesh=$E/vaselion.obj; radii=1:1:1.4 ;;
    edem:*) mesh=$E/$2.obj; pop=$E/$2.population.txt; self=1
      radii=$(radii_file "$E/$2.ellipsoid.txt") ;;
    edeq:*) mesh=$E/$2.obj; pop=$E/$2.population.txt; self=1
      radii=$(radii_file "$E/$2.ellipsoid-guess.txt") ;;
    *) die "unknown case $1:$2" ;;
  esac
  [ -f "$mesh" ] || die "no mesh $mesh"
}
report_radii() { # REPORT.json
  octave-cli -q -f --eval "r = jsondecode(fileread('$1')); printf('%.17g:%.17g:%.17g', r.radii)" 2>/dev/null
}
report_field() { # REPORT.json EXPRESSION
  octave-cli -q -f --eval "r = jsondecode(fileread('$1')); printf('%.17g', $2)" 2>/dev/null
}
metrics() { # MESH POP MAP RADII
  octave-cli -q -f "$here/octave/ellipsoid_metrics.m" "$1" "$2" "$3" "$4" 2>/dev/null \
    | sed -n 's/^ELLIPSOID //p'
}

rows=()
say "load before: $(uptime)"
for c in "${cases[@]}"; do
  kind=${c%%:*}; name=${c#*:}
  setup "$kind" "$name"
  faces=$(grep -c '^f ' "$mesh")
  out=$work/$kind.$name

  say "== $c ($faces faces): demkit"
  rc=0
  timeout -k 10 "$limit" "$demkit" map "$mesh" --method "$kind" --ellipsoid "$radii" \
    --population "$pop" --out "$out.demkit.obj" --report "$out.demkit.json" --quiet \
    >"$out.demkit.log" 2>&1 || rc=$?
  d_met=""; d_time=""; d_it=""; d_radii=""; d_note=""
  if [ $rc = 0 ] || [ $rc = 3 ]; then
    d_radii=$(report_radii "$out.demkit.json")
    d_time=$(report_field "$out.demkit.json" r.time_s.total)
    d_it=$(report_field "$out.demkit.json" r.iterations)
    d_met=$(metrics "$mesh" "$pop" "$out.demkit.obj" "$d_radii")
    [ $rc = 0 ] || d_note=" (exit 3)"
  else
    d_note=" (exit $rc)"
  fi

  say "== $c: reference under Octave"
  rc=0
  timeout -k 10 "$limit" octave-cli -q -f "$here/octave/run_reference.m" "$kind" "$code" \
    "$mesh" "$pop" "$out.ref.obj" ${radii//:/ } "$self" >"$out.ref.log" 2>&1 || rc=$?
  r_line=$(sed -n 's/^REFERENCE //p' "$out.ref.log")
  r_met=""; r_radii=$radii; r_note=""
  if [ -n "$r_line" ]; then
    chosen=$(field "$r_line" radii)
    [ -z "$chosen" ] || r_radii=$chosen
    r_met=$(metrics "$mesh" "$pop" "$out.ref.obj" "$r_radii")
  else
    r_note=" (exit $rc)"
  fi
  r_time=$(field "$r_line" time_s)
  ratio=n/a
  if [ -n "$d_time" ] && [ -n "$r_time" ]; then
    ratio=$(awk -v a="$r_time" -v b="$d_time" 'BEGIN {printf "%.1f×", a / b}')
  fi
  rows+=("| $kind | $name | $faces | $(fmt %.2f "$d_time")$d_note | $(fmt %d "$d_it") | $(fmt %.2e "$(field "$d_met" face_density_var_final)") | $(fmt %.4f "$(field "$d_met" mean_abs_mu)") | $(fmt %d "$(field "$d_met" flipped)") | $(fmt %.1f "$(field "$d_met" energy)") | $d_radii | $(fmt %.2f "$r_time")$r_note | $(fmt %d "$(field "$r_line" iterations)") | $(fmt %.2e "$(field "$r_met" face_density_var_final)") | $(fmt %.4f "$(field "$r_met" mean_abs_mu)") | $(fmt %d "$(field "$r_met" flipped)") | $(fmt %.1f "$(field "$r_met" energy)") | $r_radii | $ratio |")
  say "   demkit ${d_time:-?} s, reference ${r_time:-?} s"
done
say "load after: $(uptime)"

cat <<EOF
| method | case | faces | demkit s | it | Var | mean \|μ\| | flipped | energy | radii | ref s | ref it | ref Var | ref mean \|μ\| | ref flipped | ref energy | ref radii | ref / demkit |
| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: |
EOF
printf '%s\n' "${rows[@]}"
cat <<EOF

demkit time: the report's time_s.total. Reference time: tic/toc around what the authors' demo
runs after loading the mesh, its ellipsoidal conformal initial map included unless the surface
is its own (see octave/run_reference.m). Var: Var(ρ_F / mean ρ_F), ρ_F = P/A per face (the
demos' measure); mean |μ|: the Beltrami coefficient of the map from the input surface; flipped:
faces whose mapped corners turn inwards; energy: EDEQ's objective (α = 5) on the map and its
radii. All computed by octave/ellipsoid_metrics.m on both outputs. Outputs and logs: $work
EOF
