#!/usr/bin/env bash
# The whole test suite, run by `make test` after the debug build:
#   1. the Fortran suites (test/main.f90),
#   2. the command line: bad decks (exit 2 and the message), exit statuses, results left
#      untouched by a failed run,
#   3. the independent peer: the same embankment through CalculiX, and the other tool checks,
#   4. batch runs, studies, the comparison tool and the regression suite,
#   5. a short fuzz run of mutated decks (tools/fuzz.py; make fuzz runs 10,000).
# Every check prints PASS or FAIL; the last line is exactly `N passed, N failed`.
set -u
fortran_log=$1            # output of `fpm test` on the debug build (from the Makefile)
cfrd=build/debug-bin/cfrd
work=build/test-work
rm -rf "$work" && mkdir -p "$work"
passed=0
failed=0

pass() { echo "PASS $1"; passed=$((passed + 1)); }
fail() { echo "FAIL $1"; failed=$((failed + 1)); }

# 1. Fortran suites: count their PASS/FAIL lines.
grep -E '^(PASS|FAIL) ' "$fortran_log"
np=$(grep -c '^PASS ' "$fortran_log")
nf=$(grep -c '^FAIL ' "$fortran_log")
passed=$((passed + np))
failed=$((failed + nf))
if ! grep -q '^fortran: ' "$fortran_log"; then
    fail "fortran: the test driver did not finish; its log:"
    tail -30 "$fortran_log"
fi

# 2a. Every bad deck is rejected with exit status 2 and the message its `* expect:` card names.
for deck in test/bad_decks/*.dat; do
    [[ -e $deck ]] || continue
    expect=$(sed -n 's/^\* expect: //p' "$deck" | head -1)
    "$cfrd" --check "$deck" >"$work/out.txt" 2>"$work/err.txt"
    status=$?
    name="cli/bad-deck/$(basename "$deck" .dat)"
    if [[ $status -ne 2 ]]; then
        fail "$name: exit status $status, expected 2 ($(head -c 300 "$work/err.txt"))"
    elif ! grep -qF -- "$expect" "$work/err.txt"; then
        fail "$name: message lacks '$expect': $(head -c 300 "$work/err.txt")"
    else
        pass "$name"
    fi
done

# 2b. Exit statuses of the command line itself.
check_status() { # name expected-status command...
    local name=$1 expected=$2
    shift 2
    "$@" >"$work/out.txt" 2>"$work/err.txt"
    local status=$?
    if [[ $status -eq $expected ]]; then pass "$name"; else
        fail "$name: exit status $status, expected $expected: $(head -c 200 "$work/err.txt")"
    fi
}
check_status cli/no-deck 2 "$cfrd"
check_status cli/unknown-option 2 "$cfrd" --frobnicate inputs/example.dat
check_status cli/missing-deck-file 2 "$cfrd" "$work/no-such-deck.dat"
check_status cli/version 0 "$cfrd" --version
check_status cli/help 0 "$cfrd" --help
check_status cli/check-good-deck 0 "$cfrd" --check inputs/example.dat

# 2c. --out puts both result files in the directory named; --quiet prints nothing.
mkdir -p "$work/out"
"$cfrd" --quiet --out "$work/out" inputs/example.dat >"$work/out.txt" 2>&1
if [[ $? -eq 0 && -s $work/out/example.out && -s $work/out/example.h5 && ! -s $work/out.txt ]]
then pass cli/out-dir-and-quiet; else fail "cli/out-dir-and-quiet: $(head -c 200 "$work/out.txt")"; fi

# 2c'. Batch runs that lose nothing (issue 18): --out makes its folder; --out naming a file,
# or empty (an unset $OUT), is a usage error; two decks whose results would share names are
# refused before anything runs; a deck saved with a UTF-8 byte-order mark reads as without.
"$cfrd" --quiet --out "$work/made/for/it" inputs/example.dat >"$work/out.txt" 2>&1
if [[ $? -eq 0 && -s $work/made/for/it/example.h5 ]]; then pass cli/out-makes-its-folder
else fail "cli/out-makes-its-folder: $(head -c 200 "$work/out.txt")"; fi
touch "$work/a-file"
check_status cli/out-names-a-file 2 "$cfrd" --quiet --out "$work/a-file" inputs/example.dat
check_status cli/out-empty 2 "$cfrd" --quiet --out "" inputs/example.dat
mkdir -p "$work/twins/a" "$work/twins/b"
cp inputs/example.dat "$work/twins/a/dam.dat"
cp inputs/example.dat "$work/twins/b/dam.dat"
"$cfrd" --quiet --out "$work/twins/out" "$work/twins/a/dam.dat" "$work/twins/b/dam.dat" \
    >"$work/out.txt" 2>"$work/err.txt"
status=$?
if [[ $status -eq 2 && ! -e $work/twins/out ]] && grep -q "twins/a/dam.dat and .*twins/b/dam.dat" \
    "$work/err.txt"; then pass cli/result-name-collision
else fail "cli/result-name-collision: exit $status: $(head -c 200 "$work/err.txt")"; fi
printf '\xef\xbb\xbf' >"$work/bom.dat"
cat inputs/example.dat >>"$work/bom.dat"
check_status cli/byte-order-mark 0 "$cfrd" --check "$work/bom.dat"

# SIGTERM / SIGINT: the run stops after the stage it is in and keeps the completed stages.
tool_checks "interrupt" python3 tools/check_interrupt.py --cfrd "$cfrd" --workdir "$work/interrupt"

# 2d. A failed run leaves the results of an earlier run byte-identical, and no temporary files.
tools/cli_failure_test.sh "$cfrd" "$work/failure" && pass cli/failed-run-keeps-results ||
    fail cli/failed-run-keeps-results

# 3. Checks run by tools: each prints PASS/FAIL lines; every line counts.
tool_checks() { # name command...
    local name=$1
    shift
    "$@" >"$work/tool.txt" 2>&1
    local status=$?
    local lines
    lines=$(grep -E '^(PASS|FAIL) ' "$work/tool.txt")
    if [[ -z $lines ]]; then
        fail "$name: no verdict (exit $status): $(tail -3 "$work/tool.txt")"
        return
    fi
    while IFS= read -r line; do
        case $line in
            PASS*) pass "${line#PASS }" ;;
            FAIL*) fail "${line#FAIL }" ;;
        esac
    done <<<"$lines"
    [[ $status -eq 0 ]] || grep -q '^FAIL ' "$work/tool.txt" || fail "$name: exit $status"
}
# The independent peer: CalculiX checked on a closed form, then on the same embankment.
# The shared layer of the tools (tools/cfrdtools): deck fields, results reading, the runner.
tool_checks "cfrdtools" env PYTHONPATH=tools python3 -m cfrdtools.selftest
tool_checks "peer --column" python3 tools/ccx_peer.py --cfrd "$cfrd" --column --workdir "$work/peer"
tool_checks "peer --elements 1000" python3 tools/ccx_peer.py --cfrd "$cfrd" --elements 1000 \
    --workdir "$work/peer"
# Layer-by-layer construction against a superposition of CalculiX runs, both conventions.
tool_checks "peer thin layer" python3 tools/ccx_thin.py --cfrd "$cfrd" --workdir "$work/ccx-thin"
tool_checks "ccx staged" python3 tools/ccx_staged.py --cfrd "$cfrd" --workdir "$work/ccx-staged"
# Frictional contact between non-matching meshes: contact resultants and opened lengths against
# CalculiX's face-to-face penalty contact (issue 7).
tool_checks "peer contact" python3 tools/ccx_contact.py --cfrd "$cfrd" --workdir "$work/ccx-contact"
# Hard cases stay stable (issue 9, section 2): test/hard_cases/*.dat, each converging to a
# checked answer or stopping with the full diagnostic, no NaN or Inf, earlier results intact.
tool_checks "hard cases" python3 tools/hard_cases.py --cfrd "$cfrd" --workdir "$work/hard-cases"
# The E-B law: scipy's integration of it, checked on Kondner's hyperbola, then against
# cfrd's plane-strain compression of two Table 3 materials.
tool_checks "eb reference" python3 tools/eb_reference.py --selftest
tool_checks "eb plane strain" python3 tools/eb_reference.py --check-cfrd "$cfrd" \
    --workdir "$work/eb"

# The EFFECTS card (issue 9, section 3): each effect switched off against a closed form,
# scipy's E-B integration or an equivalent deck; no contact search in a deck without contact.
tool_checks "effects" python3 tools/check_effects.py --cfrd "$cfrd" --workdir "$work/effects"

# Rockfill creep (issue 19; docs/theory.md section 15): a triaxial element against the closed
# form, the first-order convergence of the time steps, a layered column against scipy.
tool_checks "creep" python3 tools/check_creep.py --cfrd "$cfrd" --workdir "$work/creep"

tool_checks "tianshengqiao" python3 tools/check_tianshengqiao.py --run "$cfrd" \
    --workdir "$work/tianshengqiao"
# The XDMF file read back through an independent reader (meshio) against the HDF5 datasets.
tool_checks "xdmf" python3 tools/check_xdmf.py --run "$cfrd" --workdir "$work/xdmf"
# The figures plot what the HDF5 files hold (tools/figures.py --data against h5py reads):
# the joint deck alone, then the contact deck with the joint deck (both methods in one set).
tool_checks "figures" python3 tools/check_figures.py --run "$cfrd" --workdir "$work/figures"
# The zig-zag measure of tools/interface_zigzag.py (docs/tianshengqiao.md section 7.4) on
# closed forms.
tool_checks "interface zigzag" python3 tools/interface_zigzag.py --selftest
# The arithmetic of the accuracy-cost study (docs/accuracy-cost.md): Richardson extrapolation
# of f(h) = f0 + c h^p (f0 and p to 1e-12), the refusal of non-monotone sequences, the knee.
tool_checks "accuracy cost" python3 tools/accuracy_cost.py --selftest

# 4. Results people use: batch runs, parametric studies and their Slurm arrays; the
# comparison tool; the regression suite (every deck in inputs/ against outputs/reference/).
tool_checks "batch" python3 tools/check_batch.py --cfrd "$cfrd" --workdir "$work/batch"
tool_checks "compare" python3 tools/check_compare.py --cfrd "$cfrd" --workdir "$work/compare"
tool_checks "regression" python3 tools/regression.py --cfrd "$cfrd" \
    --workdir "$work/regression"
# 5. Bad input at scale (issue 9, section 4): a short fixed-seed fuzz run, every mutant read
# with --check and every other accepted mutant of the small decks run in full; none may crash,
# hang, be rejected without FILE:LINE (and field), or write NaN (make fuzz runs 10,000).
tool_checks "fuzz" python3 tools/fuzz.py --cfrd "$cfrd" --count 500 --seed 1 --full-large 0 \
    --workdir "$work/fuzz"

echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
