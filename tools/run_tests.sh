#!/usr/bin/env bash
# The whole test suite, run by `make test` after the debug build:
#   1. the Fortran suites (test/main.f90),
#   2. the command line: bad decks (exit 2 and the message), exit statuses, results left
#      untouched by a failed run, result sets (locks, run ids, cfrd --check),
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
check_status cli/out-without-folder 2 "$cfrd" inputs/example.dat --out
check_status cli/out-empty-name 2 "$cfrd" --check --out "" inputs/example.dat

# 2b'. Usage errors that protect results (issue 18, part 4): exit 2, the message, no run.
check_message() { # name expected-status message command...
    local name=$1 expected=$2 message=$3
    shift 3
    "$@" >"$work/out.txt" 2>"$work/err.txt"
    local status=$?
    if [[ $status -ne $expected ]]; then
        fail "$name: exit status $status, expected $expected: $(head -c 300 "$work/err.txt")"
    elif ! grep -qF -- "$message" "$work/err.txt"; then
        fail "$name: message lacks '$message': $(head -c 300 "$work/err.txt")"
    else
        pass "$name"
    fi
}
# Two decks of the same name from different folders into one --out folder: refused before
# any run (the second used to overwrite the first); so is one deck named twice.
mkdir -p "$work/names/a" "$work/names/b"
cp inputs/example.dat "$work/names/a/col.dat"
cp inputs/example.dat "$work/names/b/col.dat"
mkdir -p "$work/names/same"     # an existing folder: the second deck would overwrite
check_message cli/out-same-name-refused 2 \
    "$work/names/a/col.dat and $work/names/b/col.dat would both write" \
    "$cfrd" --quiet --out "$work/names/same" "$work/names/a/col.dat" "$work/names/b/col.dat"
if [[ -e $work/names/same/col.h5 ]]; then fail "cli/out-same-name-no-run: col.h5 written"
else pass cli/out-same-name-no-run; fi
check_message cli/same-deck-twice-refused 2 "would both write" \
    "$cfrd" --quiet "$work/names/a/col.dat" "$work/names/b/../a/col.dat"
# --out naming a missing folder creates it (with its parents); naming a file is refused.
check_status cli/out-creates-folder 0 "$cfrd" --quiet --out "$work/names/new/deep" \
    "$work/names/a/col.dat"
if [[ -s $work/names/new/deep/col.h5 && -s $work/names/new/deep/col.out ]]; then
    pass cli/out-created-folder-has-results; else fail cli/out-created-folder-has-results; fi
touch "$work/names/a-file"
check_message cli/out-is-a-file 2 "a file of that name exists" \
    "$cfrd" --quiet --out "$work/names/a-file" "$work/names/a/col.dat"
# A deck saved with a UTF-8 byte-order mark reads as the same deck without it.
printf '\xef\xbb\xbf' >"$work/names/bom.dat"
cat inputs/example.dat >>"$work/names/bom.dat"
"$cfrd" --check "$work/names/bom.dat" >"$work/out.txt" 2>"$work/err.txt"
status=$?
expected=$("$cfrd" --check inputs/example.dat | sed 's/^.*: OK/OK/')
if [[ $status -eq 0 && $(sed 's/^.*: OK/OK/' "$work/out.txt") == "$expected" ]]; then
    pass "cli/utf8-bom-deck"
else
    fail "cli/utf8-bom-deck: exit $status: $(head -c 300 "$work/err.txt" "$work/out.txt")"
fi

# 2c. --out puts both result files in the directory named; --quiet prints nothing.
mkdir -p "$work/out"
"$cfrd" --quiet --out "$work/out" inputs/example.dat >"$work/out.txt" 2>&1
if [[ $? -eq 0 && -s $work/out/example.out && -s $work/out/example.h5 && ! -s $work/out.txt ]]
then pass cli/out-dir-and-quiet; else fail "cli/out-dir-and-quiet: $(head -c 200 "$work/out.txt")"; fi

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
# A run stopped by SIGTERM / SIGINT keeps its completed stages, bit for bit (issue 18).
tool_checks "stop" python3 tools/check_stop.py --cfrd "$cfrd" --workdir "$work/stop"
# Result sets (issue 24): no deck written over, one run per set at a time (DECK.lock), one
# run id in every file, all files replaced together, cfrd --check.
tool_checks "result sets" tools/result_set_test.sh "$cfrd" "$work/sets"
# Restart from a completed stage (issue 24, part 3): the same results as the run without a
# stop, to the last bit, after every stage kind of the x1 Tianshengqiao-I decks; refusals.
tool_checks "restart" python3 tools/check_restart.py --cfrd "$cfrd" --workdir "$work/restart"
# The independent peer: CalculiX checked on a closed form, then on the same embankment.
# The shared layer of the tools (tools/cfrdtools): deck fields, results reading, the runner.
tool_checks "cfrdtools" env PYTHONPATH=tools python3 -m cfrdtools.selftest
tool_checks "peer --column" python3 tools/ccx_peer.py --cfrd "$cfrd" --column --workdir "$work/peer"
tool_checks "peer --elements 1000" python3 tools/ccx_peer.py --cfrd "$cfrd" --elements 1000 \
    --workdir "$work/peer"
# Layer-by-layer construction against a superposition of CalculiX runs, both conventions.
tool_checks "peer thin layer" python3 tools/ccx_peer.py --thin --cfrd "$cfrd" \
    --workdir "$work/ccx-thin"
tool_checks "ccx staged" python3 tools/ccx_peer.py --staged --cfrd "$cfrd" \
    --workdir "$work/ccx-staged"
# Frictional contact between non-matching meshes: contact resultants and opened lengths against
# CalculiX's face-to-face penalty contact (issue 7).
tool_checks "peer contact" python3 tools/ccx_peer.py --contact --cfrd "$cfrd" \
    --workdir "$work/ccx-contact"
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

# The plinth and the perimetric joint (issue 22): two blocks against statics closed forms,
# the CSV, HDF5 and listing agreeing, the --plinth decks of every interface method read.
tool_checks "plinth" python3 tools/check_plinth.py --cfrd "$cfrd" --workdir "$work/plinth"
# The error control of the midpoint increments (issue 21) on the x1 --plinth joint deck: every
# accepted increment within ERRTOL, the same deck without control beyond it, exit 1 at DEPTH.
tool_checks "error control" python3 tools/check_error_control.py --cfrd "$cfrd" \
    --workdir "$work/errctl"
tool_checks "tianshengqiao" python3 tools/check_tianshengqiao.py --run "$cfrd" \
    --workdir "$work/tianshengqiao"
# The XDMF file read back through an independent reader (meshio) against the HDF5 datasets.
tool_checks "xdmf" python3 tools/check_results_format.py --xdmf --cfrd "$cfrd" \
    --workdir "$work/xdmf"
# How results are stored (issue 21): shuffle + deflate lossless, --float32 exactly rounded,
# its XDMF file read back by meshio, --compress usage errors (tools/check_results_format.py).
tool_checks "results format" python3 tools/check_results_format.py --cfrd "$cfrd" \
    --workdir "$work/format"
# The lean results file (issue 21, the default): every dataset of a --results full file at
# every stage equal to the lean file's or computed from it by tools/cfrdtools bit for bit,
# the links, the lean XDMF against the full one, a lean file continued as a full one.
tool_checks "results lean" python3 tools/check_results_lean.py --cfrd "$cfrd" \
    --workdir "$work/lean"
# The deflate filter computed by libdeflate (issue 21, src/io/cfrd_h5_deflate.c): the files
# read by h5py equal to --compress 0's, every chunk a zlib stream that Python's zlib inflates
# to the unfiltered values, the standard pipeline, not zlib's encoding, restart from such a file.
tool_checks "deflate" python3 tools/check_deflate.py --cfrd "$cfrd" --workdir "$work/deflate"
# The measuring aid of issue 21: CFRD_WRITE_MATRIX leaves the results bit-identical, writes
# the stage's matrix (read back by scipy), and tools/factor_floor.c solves it (x = 1).
tool_checks "matrix market" python3 tools/check_matrix_market.py --cfrd "$cfrd" \
    --workdir "$work/matrix-market"
# The OpenMP element loops (issue 21): --threads 2 and OMP_NUM_THREADS=2 give the same bits as
# --threads 1 on the x1 bonded and contact decks; the threads are started; usage errors.
tool_checks "threads" python3 tools/check_threads.py --cfrd "$cfrd" --workdir "$work/threads"
# Two runs of one program write the same bytes (listings, legacy listing, CSVs, XDMF) and the
# same HDF5 values, run ids and times aside: tools/same_outputs.py, the comparison that holds
# a speed-only change to main's outputs (docs/performance.md (r)), run on itself.
tool_checks "same outputs" python3 tools/same_outputs.py --before "$cfrd" --after "$cfrd" \
    --workdir "$work/same-outputs" --flags=--legacy-listing inputs/example.dat inputs/column.dat
# Issue 21: CHOLMOD for the SPD systems agrees with UMFPACK, the contact systems stay with
# UMFPACK, --linear-solver's usage errors (tools/check_linear_solver.py).
tool_checks "linear solver" python3 tools/check_linear_solver.py --cfrd "$cfrd" \
    --workdir "$work/linear-solver"
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
