#!/usr/bin/env bash
# A failed run must leave the results of an earlier run byte-identical (issue 3, section 2):
# run a good deck, then the same deck name with bad input (exit 2) and with a singular
# stiffness matrix (exit 1); compare checksums (listing, HDF5 file and the legacy-style
# listing) and look for leftover temporary files.
set -u
cfrd=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
deck=$dir/block.dat

write_deck() { # $1 = boundary cards, $2 = extra element card (or empty)
    cat >"$deck" <<CARDS
TITLE     two squares
CONTROL
NODES
    1    2    1       0.0       0.0       1.0       0.0
    3    4    1       0.0       1.0       1.0       1.0
    5    6    1       5.0       0.0       6.0       0.0
    7    8    1       5.0       1.0       6.0       1.0
ELEMENTS
    1    1    2    4    3    1
$2
MATERIALS
    1ELASTIC   soil
    1.0e4      0.3       20.0
BOUNDARY
$1
LOADS
GRAVITY
END
CARDS
}
# Good: both squares sit on fixed nodes.
write_deck "    1    2    1    1    1
    5    6    1    1    1" "    2    5    6    8    7    1"
"$cfrd" --quiet --legacy-listing "$deck" || { echo "good deck failed"; exit 1; }
before=$(sha256sum "$dir/block.out" "$dir/block.h5" "$dir/block.lst")

# Bad input: a negative Young's modulus.
write_deck "    1    2    1    1    1
    5    6    1    1    1" "    2    5    6    8    7    1"
sed -i 's/^    1.0e4 /   -1.0e4 /' "$deck"
"$cfrd" --quiet --legacy-listing "$deck" 2>/dev/null
[[ $? -eq 2 ]] || { echo "bad deck did not exit 2"; exit 1; }

# Numerical failure: the second square floats (its nodes are not supported).
write_deck "    1    2    1    1    1" "    2    5    6    8    7    1"
"$cfrd" --quiet --legacy-listing "$deck" 2>"$dir/err.txt"
status=$?
[[ $status -eq 1 ]] || { echo "floating square: exit $status, expected 1"; cat "$dir/err.txt"; exit 1; }
grep -q "singular" "$dir/err.txt" || { echo "no 'singular' in: $(cat "$dir/err.txt")"; exit 1; }

after=$(sha256sum "$dir/block.out" "$dir/block.h5" "$dir/block.lst")
[[ $before == "$after" ]] || { echo "results changed"; exit 1; }
if ls "$dir"/*.part >/dev/null 2>&1; then echo "temporary files left"; exit 1; fi
exit 0
