#!/usr/bin/env bash
# Side-by-side run of demkit and the authors' MATLAB reference code (run under GNU Octave) on
# the same meshes: time, iterations and density error of each, as a markdown table on stdout.
# See bench/reference/README.md.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/reference/lib.sh
. "$here/lib.sh"
root=$(cd "$here/../.." && pwd)

usage() {
  cat <<EOF
Usage: bench/reference/compare.sh [options] [CASE...]

  --sdem DIR     the authors' SDEM code (github.com/garyptchoi/spherical-density-equalizing-map):
                 a checkout, or a git directory (bare or .git) whose HEAD is exported with
                 git archive into the work directory       [env DEMKIT_REF_SDEM]
  --tdem DIR     the same for garyptchoi/toroidal-density-equalizing-map [env DEMKIT_REF_TDEM]
  --data DIR     the real meshes (genus0/, genus1/)
                 [env DEMKIT_DATA, default ../shared/data beside the checkout]
  --demkit BIN   the demkit binary [target/release/demkit; built if missing]
  --timeout S    time limit of each run, in seconds [1800]
  --work DIR     where exports, outputs and logs go [a new temporary directory, kept]

CASE: david1 twistedball maxplanck duck brain (SDEM), torus_1 torus_4 torus_5_1 (TDEM on the
authors' example tori), bob vertebra (TDEM parameterization); default: all of them.
EOF
}


sdem_src=${DEMKIT_REF_SDEM:-}
tdem_src=${DEMKIT_REF_TDEM:-}
data=${DEMKIT_DATA:-$root/../shared/data}
demkit=""
limit=1800
work=""
cases=()
while [ $# -gt 0 ]; do
  case $1 in
    --sdem) sdem_src=$2; shift 2 ;;
    --tdem) tdem_src=$2; shift 2 ;;
    --data) data=$2; shift 2 ;;
    --demkit) demkit=$2; shift 2 ;;
    --timeout) limit=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) usage >&2; die "unknown option $1" ;;
    *) cases+=("$1"); shift ;;
  esac
done
[ ${#cases[@]} -gt 0 ] || cases=(david1 twistedball maxplanck duck brain torus_1 torus_4 torus_5_1 bob vertebra)

command -v octave-cli >/dev/null || die "octave-cli not found (apt-get install octave)"
[ -d "$data/genus0" ] && [ -d "$data/genus1" ] || die "no meshes in $data (give --data or DEMKIT_DATA)"
data=$(cd "$data" && pwd)
if [ -z "$demkit" ]; then
  demkit=$root/target/release/demkit
  if [ ! -x "$demkit" ]; then
    say "building demkit (release) ..."
    (cd "$root" && cargo build --release --bin demkit) >&2
  fi
fi
[ -x "$demkit" ] || die "no demkit binary at $demkit"
if [ -z "$work" ]; then
  work=$(mktemp -d "${TMPDIR:-/tmp}/demkit-reference.XXXXXX")
fi
mkdir -p "$work"
work=$(cd "$work" && pwd)

need_sdem=0; need_tdem=0
for c in "${cases[@]}"; do
  case $c in
    david1|twistedball|maxplanck|duck|brain) need_sdem=1 ;;
    torus_1|torus_4|torus_5_1|bob|vertebra) need_tdem=1 ;;
    *) die "unknown case $c" ;;
  esac
done
[ $need_sdem = 0 ] || sdem_code=$(code_dir "$sdem_src" sdem)
[ $need_tdem = 0 ] || tdem_code=$(code_dir "$tdem_src" tdem)

octave=(octave-cli -q -f)
rows=()
details=()
say "load before: $(uptime)"
for c in "${cases[@]}"; do
  pop=area; popargs=()
  case $c in
    david1|twistedball|maxplanck|duck|brain)
      kind=sdem; domain=sphere; mesh=$data/genus0/$c.obj
      if [ -f "$data/genus0/$c.population.txt" ]; then pop=$data/genus0/$c.population.txt; fi
      demkit_args=(--method sdem)
      ref_args=(sdem "$sdem_code" "$mesh") ;;
    torus_1|torus_4|torus_5_1|bob|vertebra)
      domain=torus; mesh=$data/genus1/$c.obj
      R=$(awk '$1 == "R" {print $2}' "$data/genus1/$c.torus.txt")
      r=$(awk '$1 == "r" {print $2}' "$data/genus1/$c.torus.txt")
      demkit_args=(--method tdem --torus "$R:$r")
      if [ -f "$data/genus1/$c.population.txt" ]; then
        kind=torus; pop=$data/genus1/$c.population.txt
        ref_args=(torus "$tdem_code" "$mesh")
        ref_extra=("$tdem_code/data/example_$c.mat" "$R" "$r")
      else
        kind=param
        ref_args=(param "$tdem_code" "$mesh")
        ref_extra=("$data/genus1/$c.cut-edges.txt" "$R" "$r")
      fi ;;
  esac
  [ "$pop" = area ] || popargs=(--population "$pop")
  faces=$(grep -c '^f ' "$mesh")
  out=$work/$c

  say "== $c ($faces faces): demkit"
  rc=0; t0=$(now)
  timeout -k 10 "$limit" "$demkit" map "$mesh" "${demkit_args[@]}" "${popargs[@]}" \
    --out "$out.demkit.obj" --report "$out.demkit.json" --quiet >"$out.demkit.log" 2>&1 || rc=$?
  t1=$(now)
  d_wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN {print b - a}')
  d_line=""; d_rep=""
  if [ $rc = 0 ] || [ $rc = 3 ]; then
    m=$("${octave[@]}" "$here/octave/metrics.m" "$mesh" "$pop" "$out.demkit.obj" "$domain" \
          "$out.demkit.json" 2>>"$out.demkit.log")
    d_line=$(echo "$m" | sed -n 's/^METRICS //p')
    d_rep=$(echo "$m" | sed -n 's/^REPORT //p')
    d_note=""; [ $rc = 0 ] || d_note=" (not converged)"
  elif [ $rc = 124 ] || [ $rc = 137 ]; then
    d_note=" (timeout ${limit} s)"
  else
    d_note=" (failed: exit $rc, see $out.demkit.log)"
  fi

  say "== $c: reference under Octave"
  rc=0
  case $kind in
    sdem) full=("${ref_args[@]}" "$pop" "$out.ref.obj") ;;
    torus) full=("${ref_args[@]}" "$pop" "$out.ref.obj" "${ref_extra[@]}") ;;
    param) full=("${ref_args[@]}" area "$out.ref.obj" "${ref_extra[@]}") ;;
  esac
  t0=$(now)
  timeout -k 10 "$limit" "${octave[@]}" "$here/octave/run_reference.m" "${full[@]}" \
    >"$out.ref.log" 2>&1 || rc=$?
  t1=$(now)
  r_wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN {print b - a}')
  r_line=$(sed -n 's/^REFERENCE //p' "$out.ref.log")
  r_met=""; r_note=""
  if [ -n "$r_line" ]; then
    r_met=$("${octave[@]}" "$here/octave/metrics.m" "$mesh" "$pop" "$out.ref.obj" "$domain" \
              2>>"$out.ref.log" | sed -n 's/^METRICS //p')
    it=$(field "$r_line" iterations)
    if { [ $kind = sdem ] && [ "$it" -ge 200 ]; } || [ "$it" -gt 500 ]; then r_note=" (max_iter)"; fi
  elif [ $rc = 124 ] || [ $rc = 137 ]; then
    r_note=" (timeout ${limit} s)"
  else
    r_note=" (failed: exit $rc, see $out.ref.log)"
  fi

  d_time=$(field "$d_rep" total_s); r_time=$(field "$r_line" time_s)
  ratio=n/a
  if [ -n "$d_time" ] && [ -n "$r_time" ]; then
    ratio=$(awk -v a="$r_time" -v b="$d_time" 'BEGIN {printf "%.1f×", a / b}')
  fi
  rows+=("| $c | $faces | $(fmt %.2f "$d_time") ($(fmt %.2f "$d_wall")) | $(fmt %d "$(field "$d_rep" iterations)")$d_note | $(fmt %.4f "$(field "$d_line" density_error_mean)") | $(fmt %.2f "$r_time") | $(fmt %d "$(field "$r_line" iterations)")$r_note | $(fmt %.4f "$(field "$r_met" density_error_mean)") | $ratio |")
  details+=("| $c | $(fmt %.2e "$(field "$d_line" density_var_final)") | $(fmt %.2e "$(field "$r_met" density_var_final)") | $(fmt %d "$(field "$d_line" flipped)") / $(fmt %d "$(field "$r_met" flipped)") | $(fmt %.6f "$(field "$d_rep" density_error_mean)") / $(fmt %.6f "$(field "$d_line" density_error_mean)") | $(fmt %.2f "$(field "$r_line" init_s)") + $(fmt %.2f "$(field "$r_line" method_s)") | $(fmt %.1f "$r_wall") |")
  say "   demkit ${d_time:-?} s, reference ${r_time:-?} s"
done
say "load after: $(uptime)"

cat <<EOF
| case | faces | demkit time s (wall) | demkit it | demkit mean \|d\| | ref time s | ref it | ref mean \|d\| | ref / demkit |
| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |
EOF
printf '%s\n' "${rows[@]}"
cat <<EOF

| case | demkit Var(ρ̃) | ref Var(ρ̃) | flipped demkit / ref | demkit mean \|d\|: report / Octave | ref init + method s | ref process wall s |
| --- | ---: | ---: | ---: | ---: | ---: | ---: |
EOF
printf '%s\n' "${details[@]}"
cat <<EOF

demkit time: the report's time_s.total (wall: the whole process). Reference time: tic/toc around
what the authors' demo runs after loading the mesh (see octave/run_reference.m). mean |d|: mean
over faces of |log((A/ΣA)/(P/ΣP))| on the output map, A the area of the flat triangle between the
mapped corners (unit sphere; torus in R³); Var(ρ̃): Var(ρ_V/mean ρ_V), ρ_V the area-weighted
average of P/A over each vertex's faces. Both computed by octave/density_metrics.m for both
outputs, as crates/demkit/src/metrics.rs defines them. Flips on the sphere only (n/a: torus).
Outputs and logs: $work
EOF
