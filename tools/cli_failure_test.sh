#!/usr/bin/env bash
# A failed run must leave the results of an earlier run byte-identical (issue 3, section 2)
# and keep what it completed in DECK.incomplete.h5 (issue 8, section 1; docs/results.md):
#   1. a good staged deck (two squares placed one after the other) writes block.out, .h5, .xmf
#      and the legacy-style listing block.lst;
#   2. bad input (exit 2) changes nothing and writes nothing;
#   (every later run asks for the legacy-style listing too, which must stay untouched)
#   3. the second square floating (singular at stage 2, exit 1): the earlier files are
#      byte-identical, no *.part file is left, block.incomplete.h5 has complete = 0,
#      stages_completed = 1, the failure message, and its stage 1 equals stage 1 of the good
#      run bit for bit (the same computation); block.incomplete.xmf points at it;
#   4. a deck singular at its first stage replaces block.incomplete.h5 (0 stages, no .xmf);
#   5. the good deck again: the incomplete files are removed;
#   6. a run killed (SIGKILL) after its third stage leaves DECK.h5.part readable with
#      complete = 0 and the stages it counted.
set -u
cfrd=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
deck=$dir/block.dat

write_deck() { # $1 = boundary cards, $2 = STAGES group (or empty)
    cat >"$deck" <<CARDS
TITLE     two squares
CONTROL
NODES
    1    2    1       0.0       0.0       1.0       0.0
    3    4    1       0.0       1.0       1.0       1.0
    5    6    1       5.0       0.0       6.0       0.0
    7    8    1       5.0       1.0       6.0       1.0
ELEMENTS
    1    1    2    4    3    1              A
    2    5    6    8    7    1              B
MATERIALS
    1ELASTIC   soil
    1.0e4      0.3       20.0
BOUNDARY
$1
LOADS
GRAVITY
$2
END
CARDS
}
both_fixed="    1    2    1    1    1
    5    6    1    1    1"
staged="STAGES
FILL      A             1
FILL      B             1"

fail() { echo "$1"; exit 1; }

# 1. Good: both squares sit on fixed nodes, placed one after the other.
write_deck "$both_fixed" "$staged"
"$cfrd" --quiet --legacy-listing "$deck" || fail "good deck failed"
results="$dir/block.out $dir/block.h5 $dir/block.xmf $dir/block.lst"
before=$(sha256sum $results)

# 2. Bad input: a negative Young's modulus.
sed -i 's/^    1.0e4 /   -1.0e4 /' "$deck"
"$cfrd" --quiet --legacy-listing "$deck" 2>/dev/null
[[ $? -eq 2 ]] || fail "bad deck did not exit 2"
[[ -e $dir/block.incomplete.h5 ]] && fail "bad input wrote block.incomplete.h5"

# 3. Numerical failure at stage 2: the second square floats (its nodes are not supported).
write_deck "    1    2    1    1    1" "$staged"
"$cfrd" --quiet --legacy-listing "$deck" 2>"$dir/err.txt"
status=$?
[[ $status -eq 1 ]] || { cat "$dir/err.txt"; fail "floating square: exit $status, expected 1"; }
grep -q "singular" "$dir/err.txt" || fail "no 'singular' in: $(cat "$dir/err.txt")"
after=$(sha256sum $results)
[[ $before == "$after" ]] || fail "results changed"
if ls "$dir"/*.part >/dev/null 2>&1; then fail "temporary files left: $(ls "$dir"/*.part)"; fi
python3 - "$dir" <<'PY' || fail "block.incomplete.h5 after a failure at stage 2"
import sys, h5py, numpy as np
d = sys.argv[1]
with h5py.File(f"{d}/block.incomplete.h5", "r") as f, h5py.File(f"{d}/block.h5", "r") as good:
    a = f.attrs
    assert a["complete"] == 0 and a["stages_completed"] == 1 and a["stages_total"] == 2, dict(a)
    assert b"singular" in a["failure"] and b"stage 2" in a["failure"], a["failure"]
    assert list(f["stages"]) == ["stage_0001"], list(f["stages"])
    assert good.attrs["complete"] == 1
    for name in ("displacement", "stress_gauss", "active"):
        assert np.array_equal(f["stages/stage_0001"][name][...],
                              good["stages/stage_0001"][name][...]), name
xmf = open(f"{d}/block.incomplete.xmf").read()
assert xmf.count("<Time ") == 1 and "block.incomplete.h5:/stages/stage_0001/" in xmf
PY

# 4. Numerical failure at the first stage (no STAGES: one LOADS stage).
write_deck "    1    2    1    1    1" ""
"$cfrd" --quiet "$deck" 2>"$dir/err.txt"
[[ $? -eq 1 ]] || fail "floating square, one stage: exit status not 1"
[[ $before == "$(sha256sum $results)" ]] || fail "results changed"
if ls "$dir"/*.part >/dev/null 2>&1; then fail "temporary files left: $(ls "$dir"/*.part)"; fi
[[ -e $dir/block.incomplete.xmf ]] && fail "block.incomplete.xmf left for a run with no stage"
python3 - "$dir" <<'PY' || fail "block.incomplete.h5 after a failure at stage 1"
import sys, h5py
with h5py.File(f"{sys.argv[1]}/block.incomplete.h5", "r") as f:
    assert f.attrs["complete"] == 0 and f.attrs["stages_completed"] == 0, dict(f.attrs)
    assert len(f["stages"]) == 0 and f["mesh/coordinates"].shape == (8, 2)
PY

# 5. A good run removes the incomplete files of the earlier failure.
write_deck "$both_fixed" "$staged"
"$cfrd" --quiet "$deck" || fail "good deck failed the second time"
[[ -e $dir/block.incomplete.h5 || -e $dir/block.incomplete.xmf ]] &&
    fail "incomplete files left after a good run"

# 6. Killed after its third stage (the progress line follows the stage's flush).
mkdir -p "$dir/killed"
"$cfrd" --out "$dir/killed" inputs/embankment-eb.dat >"$dir/killed/log.txt" 2>&1 &
pid=$!
for _ in $(seq 1 600); do
    grep -q "stage 3/" "$dir/killed/log.txt" && break
    sleep 0.01
done
kill -9 "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
[[ -e $dir/killed/embankment-eb.h5 ]] && fail "the run ended before it could be killed"
python3 - "$dir/killed/embankment-eb.h5.part" <<'PY' || fail "killed run: .part not readable"
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    n = int(f.attrs["stages_completed"])
    assert f.attrs["complete"] == 0 and 3 <= n < f.attrs["stages_total"], dict(f.attrs)
    for s in range(1, n + 1):
        assert f[f"stages/stage_{s:04d}/displacement"].shape == f["mesh/coordinates"].shape
PY
exit 0
