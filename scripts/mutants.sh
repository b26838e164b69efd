#!/usr/bin/env bash
# The mutation check of core's soundness tests (docs/testing.md): each
# hand-written mutation below puts back a bug on a soundness-critical line
# (an outward rounding dropped, a strict comparison made loose, a filter
# removed, a sign flipped, ...), one at a time, in a scratch copy of the
# tree, and runs the tests meant to catch it (those of the module it
# touches). A mutation is "killed" when those tests fail (or time out),
# "survived" when they pass. Every mutation must be killed: the script
# exits 1 when one survives, 2 when one cannot be applied (its line
# changed: update the mutation) or its mutant does not build.
#
# Not part of `make test` (a rebuild of core and its tests per mutation:
# 10 to 20 minutes on two cores). Usage:
#   scripts/mutants.sh            every mutation
#   scripts/mutants.sh a d g      the named ones
#   scripts/mutants.sh --list     list them
# The copy (the working tree as it is, uncommitted changes included, no
# target/) and its own target directory live in $MUTANTS_DIR (default
# ${TMPDIR:-/tmp}/nvector-mutants); logs in $MUTANTS_DIR/logs/ID.log, the
# summary in $MUTANTS_DIR/summary.txt. Proptests run with CI=true (fixed
# seeds, tests/common/mod.rs): the same cases every run; PROPTEST_SEED
# overrides it. MUTANT_TIMEOUT (seconds, default 1800) bounds each run.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

ids=() descs=() files=() olds=() news=() tests=()
# mutant ID FILE DESCRIPTION OLD NEW TARGETS...: a target is `lib:FILTER`
# (core's unit tests whose path contains FILTER) or PATH (core/tests/PATH.rs:
# interval_props, its own executable, or a module of `integration`, e.g.
# shapes/props, run as the filter `shapes::props::`).
mutant() {
  ids+=("$1") files+=("$2") descs+=("$3") olds+=("$4") news+=("$5")
  shift 5
  tests+=("$*")
}

# --- Seven that once survived the tests (each now has a test that kills it)
mutant a core/src/shapes/shape.rs "tangent shapes called disjoint (< to <= in Shape::disjoint)" \
  '(r1 + r2).hi() < dd.lo()' '(r1 + r2).hi() <= dd.lo()' \
  lib:shapes::shape shapes/props
mutant b core/src/contractors/motion_chain.rs "outward rounding dropped in the forward sweep step" \
  '(pred(q.lo() + d.lo()), succ(q.hi() + d.hi()))' '(q.lo() + d.lo(), q.hi() + d.hi())' \
  slam/contractors
mutant c core/src/slam/robust/passes.rs "outward rounding dropped in the robust evidence sums (add_lo)" \
  'let s = pred(a + b);' 'let s = a + b;' \
  lib:slam::robust slam/robust/planted slam/robust/boundary
mutant d core/src/contractors/distance.rs "the distance contractor loses the true range (r cut by one axis)" \
  '*r = r.intersect(sum.sqrt());' '*r = r.intersect(s[0].sqrt());' \
  lib:contractors::distance slam/contractors
mutant e core/src/shapes/registration.rs "the registration's injectivity filter removed" \
  'if (0..g).any(|h| assign[h] == i && distinct(g, h)) {' \
  'if false && (0..g).any(|h| assign[h] == i && distinct(g, h)) {' \
  lib:shapes::registration shapes/registration_props
mutant f core/src/slam/diagnose.rs "diagnose silently drops a consistent detection" \
  'kept.extend_from_slice(&rest[..lo]);' 'kept.extend_from_slice(&rest[lo.min(1)..lo]);' \
  lib:slam::diagnose slam/diagnose
mutant g core/src/interval.rs "Interval::add not tightest (an exact sum moved one ulp down)" \
  'if s.is_finite() && two_sum_err(a, b, s) >= 0.0 {' 'if s.is_finite() && two_sum_err(a, b, s) > 0.0 {' \
  lib:interval interval_props

# --- More soundness-critical lines -----------------------------------------
mutant h core/src/interval.rs "sqr: the lower bound rounded to nearest" \
  'down(a.lo * a.lo).max(0.0)' '(a.lo * a.lo).max(0.0)' \
  lib:interval interval_props
mutant i core/src/interval.rs "sqrt: the upper bound rounded to nearest" \
  'Interval::new(lo, up(libm::sqrt(x.hi)))' 'Interval::new(lo, libm::sqrt(x.hi))' \
  lib:interval interval_props
mutant j core/src/contractors/bearing.rs "bearing in 3-D: the slant range taken for the horizontal one" \
  'let rho = if p.len() >= 3 {' 'let rho = if p.len() >= 4 {' \
  lib:contractors::bearing slam/contractors
mutant k core/src/contractors/motion_chain.rs "unicycle displacement: the motion error dropped on y" \
  '[v * heading.cos() + e, v * heading.sin() + e]' '[v * heading.cos() + e, v * heading.sin()]' \
  lib:contractors::motion_chain slam/contractors
mutant l core/src/nvector/nvalue.rs "atmost_nvalue: touching intervals counted as two values" \
  'if !placed || l > p_image || l == p_image && domains[i].lo() > p {' \
  'if !placed || l > p_image || l == p_image && domains[i].lo() >= p {' \
  lib:nvector nvector/props nvector/examples
mutant m core/src/nvector/independent.rs "independent: touching boxes taken as disjoint witnesses" \
  'if !placed || boxes[i as usize][seed_axis].lo() > p {' \
  'if !placed || boxes[i as usize][seed_axis].lo() >= p {' \
  lib:nvector nvector/props nvector/examples
mutant n core/src/nvector/hitting_set.rs "exact: a value feasible with n - 1 more points refused" \
  'if self.min_cover(all & !m)? < n {' 'if self.min_cover(all & !m)? + 1 < n {' \
  lib:nvector nvector/props nvector/examples
mutant o core/src/shapes/shape.rs "Shape::disjoint: the hole test uses the nearest centres" \
  '(dd + r1).hi() < r2.lo()' '(r1.hi() + dd.lo()) < r2.lo()' \
  lib:shapes::shape shapes/props
mutant p core/src/shapes/branch.rs "branch: only the first box of a region tried" \
  'for b in r.boxes() {' 'for b in r.boxes().iter().take(1) {' \
  lib:shapes::branch shapes/props
mutant q core/src/shapes/chain_sums.rs "chain sums: p(t) - p(s) for s > t without its sign" \
  '*o = if s < t { forward } else { -forward };' '*o = forward;' \
  lib:shapes::chain_sums shapes/frames_planted shapes/props
mutant r core/src/shapes/frames.rs "frames: a piece translated the wrong way" \
  'axes[i] = x[i] + delta[i];' 'axes[i] = x[i] - delta[i];' \
  lib:shapes::frames shapes/frames_planted shapes/props
mutant s core/src/shapes/witnesses.rs "witnesses: an item disjoint from one chosen (not all) added" \
  'if chosen.iter().all(|&c| disjoint(c, i)) {' 'if chosen.iter().any(|&c| disjoint(c, i)) {' \
  lib:shapes::witnesses shapes/props
mutant t core/src/slam/robust/mod.rs "outliers: the q-th instead of the (q+1)-th evidence bound" \
  'votes, budget + 1)' 'votes, budget)' \
  lib:slam::robust slam/robust/planted slam/robust/boundary

if [ "${1:-}" = --list ]; then
  for x in "${!ids[@]}"; do
    printf '%s  %-32s %s\n     tests: %s\n' "${ids[$x]}" "${files[$x]#core/src/}" "${descs[$x]}" "${tests[$x]}"
  done
  exit 0
fi
want=("$@")

work=${MUTANTS_DIR:-${TMPDIR:-/tmp}/nvector-mutants}
copy=$work/repo
mkdir -p "$work/logs"
export CARGO_TARGET_DIR=$work/target CI=true
# A first run starts from the tree's own debug build (the dependencies are
# reused; core itself is rebuilt at its new path).
if [ ! -d "$CARGO_TARGET_DIR/debug" ] && [ -d "$root/target/debug" ]; then
  mkdir -p "$CARGO_TARGET_DIR"
  cp -a "$root/target/debug" "$CARGO_TARGET_DIR/debug"
fi
timeout_s=${MUTANT_TIMEOUT:-1800}

# The scratch copy: tracked and untracked (not ignored) files as they are.
rm -rf "$copy"
mkdir -p "$copy"
git ls-files -z --cached --others --exclude-standard |
  tar --null -T - -cf - | tar -xmf - -C "$copy"
# (-m: the copied files get new times, newer than any build of a mutant
# left in the target directory by an earlier run, so cargo rebuilds them)
cd "$copy"

# The test executable of core/tests/PATH.rs: interval_props alone, every
# other file a module of `integration` (core/tests/main.rs).
test_exe() {
  if [ "$1" = interval_props ]; then echo interval_props; else echo integration; fi
}

# The targets of a mutation that exist (it may name a test file another
# branch adds), as cargo arguments for a build: --lib, --test EXECUTABLE.
build_args() {
  local out=() t
  for t in $1; do
    case $t in
  lib:*) out+=(--lib) ;;
      *) [ -f "core/tests/$t.rs" ] && out+=(--test "$(test_exe "$t")") ;;
    esac
  done
  echo "${out[*]}"
}

# Runs the targets one by one (a unit-test filter applies to the library
# alone); stops at the first that fails and returns its status.
run_targets() {
  local t
  for t in $1; do
    case $t in
  lib:*) cargo test -q -p nvector-core --lib -- "${t#lib:}" || return $? ;;
      *) [ -f "core/tests/$t.rs" ] || continue
         if [ "$t" = interval_props ]; then
           cargo test -q -p nvector-core --test interval_props || return $?
         else
           cargo test -q -p nvector-core --test integration -- "${t//\//::}::" || return $?
         fi ;;
    esac
  done
}

# Swaps `old` for `new` in `file` (exactly one occurrence), or fails.
apply() {
  python3 - "$1" "$2" "$3" <<'EOF'
import sys
path, old, new = sys.argv[1:]
text = open(path).read()
n = text.count(old)
if n != 1:
    sys.exit(f"{path}: the mutated text occurs {n} times (expected once): {old!r}")
open(path, "w").write(text.replace(old, new))
EOF
}

selected() {
  [ ${#want[@]} -eq 0 ] && return 0
  local w
  for w in "${want[@]}"; do [ "$w" = "$1" ] && return 0; done
  return 1
}

summary=$work/summary.txt
: >"$summary"
echo "mutants: copy in $copy, target $CARGO_TARGET_DIR, CI=true, $(date -u +%FT%TZ)" | tee -a "$summary"
# Baseline: every selected mutation's tests pass on the unmutated copy.
all_tests=""
for x in "${!ids[@]}"; do
  selected "${ids[$x]}" && all_tests="$all_tests ${tests[$x]}"
done
all_tests=$(echo "$all_tests" | tr ' ' '\n' | sort -u | tr '\n' ' ')
if ! run_targets "$all_tests" >"$work/logs/baseline.log" 2>&1; then
  echo "mutants: the tests fail WITHOUT any mutation ($work/logs/baseline.log)" | tee -a "$summary"
  exit 2
fi
echo "baseline: the tests pass unmutated" | tee -a "$summary"

killed=0 survived=0 broken=0
for x in "${!ids[@]}"; do
  id=${ids[$x]}
  selected "$id" || continue
  f=${files[$x]}
  t=${tests[$x]}
  log=$work/logs/$id.log
  cp "$root/$f" "$f"
  start=$SECONDS
  if ! apply "$f" "${olds[$x]}" "${news[$x]}" >"$log" 2>&1; then
    status="NOT APPLIED"
    broken=$((broken + 1))
  # shellcheck disable=SC2046 # the argument list is meant to split
  elif ! cargo test -q -p nvector-core --no-run $(build_args "$t") >>"$log" 2>&1; then
    status="NO BUILD"
    broken=$((broken + 1))
  else
    rc=0
    export -f run_targets
    timeout "$timeout_s" bash -c 'run_targets "$1"' _ "$t" >>"$log" 2>&1 || rc=$?
    if [ $rc -eq 0 ]; then
      status=SURVIVED
      survived=$((survived + 1))
    else
      status=killed
      [ $rc -eq 124 ] && status="killed (timeout)"
      killed=$((killed + 1))
    fi
  fi
  cp "$root/$f" "$f"
  # Failures the mutant made proptest persist are not the tree's.
  find core/tests -name '*.proptest-regressions' | while read -r r; do
    [ -f "$root/$r" ] && cp "$root/$r" "$r" || rm -f "$r"
  done
  failing=$(grep -E -- '--- FAILED|^test .* FAILED' "$log" | grep -v '^test result' | sed -E 's/^test //; s/ \.\.\. FAILED| --- FAILED//' | sort -u | head -4 | tr '\n' ' ' || true)
  printf '%-2s %-16s %4ss  %-40s %s | %s\n' "$id" "$status" $((SECONDS - start)) "${f#core/src/}" "${descs[$x]}" "${failing:-}" | tee -a "$summary"
done
echo "mutants: $killed killed, $survived survived, $broken not applied or not built" | tee -a "$summary"
[ $broken -eq 0 ] || exit 2
[ $survived -eq 0 ] || exit 1
