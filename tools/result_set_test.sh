#!/usr/bin/env bash
# Result sets (issue 24, parts 1 and 2; docs/results.md, "Result sets"): a run never writes
# over a file it did not make, and the files of a run are one set, written together.
# Each fault of the issue is a check here; each prints PASS or FAIL and counts in make test:
#   1. a deck named .out, .h5 or .xmf (or a link of that name, or another deck on the same
#      command line that a run would write) is refused with exit 2 naming both, and left
#      byte-identical; `--out ""` is a usage error;
#   2. a second run of a set being written is refused at once (exit 2, naming the first
#      run's pid, host and start), writes nothing and leaves the earlier set byte-identical
#      while the first runs; the first ends whole (cfrd --check: exit 0);
#   3. a stale lock (dead pid, this host) is taken over with a warning; a lock of another
#      host is not; the lock is gone after a good run, a failed one and SIGTERM;
#   4. every file of a set carries the run id of its results file, which records the deck's
#      SHA-256 (against sha256sum) and lists the set's files;
#   5. a rename that fails at the end (a folder in the way of one file) leaves the earlier
#      set byte-identical, not half replaced; a file of an earlier run that this one does not
#      write (DECK.lst) is removed;
#   6. cfrd --check: whole (0), a mixed set (1, naming the file), a changed deck (1), no set
#      or a bad path (2).
# Usage: tools/result_set_test.sh CFRD WORKDIR
set -u
cfrd=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
host=$(hostname)

pass() { echo "PASS set/$1"; }
fail() { echo "FAIL set/$1"; }
verdict() { # name condition-status message
    if [[ $2 -eq 0 ]]; then pass "$1"; else fail "$1: $3"; fi
}
run() { # run cfrd, keeping stdout, stderr and status in $dir/out.txt, err.txt, $status
    "$cfrd" "$@" >"$dir/out.txt" 2>"$dir/err.txt"
    status=$?
}
h5attr() { # file attribute: a root attribute of an HDF5 file as text
    python3 -c 'import sys, h5py
v = h5py.File(sys.argv[1], "r").attrs.get(sys.argv[2], b"")
print(v.decode() if isinstance(v, bytes) else v)' "$1" "$2"
}
same_files() { # the sha256 of files, to compare before and after
    sha256sum "$@" 2>&1
}

# 1. Decks that a run would write over.
mkdir -p "$dir/decks"
for ending in out h5 xmf; do
    cp inputs/example.dat "$dir/decks/col.$ending"
    run --quiet "$dir/decks/col.$ending"
    ok=1
    [[ $status -eq 2 ]] || ok=0
    grep -qF "$dir/decks/col.$ending: the run would write $dir/decks/col.$ending, which is the deck itself" \
        "$dir/err.txt" || ok=0
    cmp -s inputs/example.dat "$dir/decks/col.$ending" || ok=0
    [[ -z $(ls "$dir/decks" | grep -v "^col\.$ending\$") ]] || ok=0
    verdict "deck-named-$ending-refused" $((1 - ok)) \
        "exit $status, $(head -c 300 "$dir/err.txt"), files: $(ls "$dir/decks")"
    rm -f "$dir/decks"/*
done
# A link named as a result file: the rename would replace the link.
cp inputs/example.dat "$dir/decks/real.dat"
ln -s real.dat "$dir/decks/link.out"
run --quiet "$dir/decks/link.out"
[[ $status -eq 2 && -L $dir/decks/link.out && ! -e $dir/decks/link.h5 ]] &&
    grep -qF "which is the deck itself" "$dir/err.txt"
verdict deck-link-named-out-refused $? "exit $status: $(head -c 300 "$dir/err.txt")"
# Another deck of the same command line that a run would write (dam-gauges.csv of dam.dat).
cp inputs/example.dat "$dir/decks/dam.dat"
cp inputs/example.dat "$dir/decks/dam-gauges.csv"
run --quiet "$dir/decks/dam.dat" "$dir/decks/dam-gauges.csv"
[[ $status -eq 2 && ! -e $dir/decks/dam.h5 ]] && cmp -s inputs/example.dat "$dir/decks/dam-gauges.csv" &&
    grep -qF "$dir/decks/dam.dat: the run would write $dir/decks/dam-gauges.csv, which is the deck $dir/decks/dam-gauges.csv" "$dir/err.txt"
verdict other-deck-refused $? "exit $status: $(head -c 300 "$dir/err.txt")"
# With --out, the deck inside the folder of the results.
mkdir -p "$dir/decks/into"
cp inputs/example.dat "$dir/decks/into/example.xmf"
run --quiet --out "$dir/decks/into" "$dir/decks/into/example.xmf"
[[ $status -eq 2 ]] && cmp -s inputs/example.dat "$dir/decks/into/example.xmf"
verdict deck-in-out-folder-refused $? "exit $status: $(head -c 300 "$dir/err.txt")"
# An unset $OUT in a job script: `--out ""` is a usage error, not the root folder. A deck
# name of its own, so that a binary with the fault writes /cfrd-set-test-out.* (removed
# again here) and nothing of anyone else's.
root_files="/cfrd-set-test-out.out /cfrd-set-test-out.h5 /cfrd-set-test-out.xmf"
if ls $root_files >/dev/null 2>&1; then
    fail "out-empty-refused: $root_files exist already: not run"
else
    cp inputs/example.dat "$dir/decks/cfrd-set-test-out.dat"
    run --quiet --out "" "$dir/decks/cfrd-set-test-out.dat"
    written=$(ls $root_files 2>/dev/null)
    rm -f $root_files
    [[ $status -eq 2 && -z $written ]] && grep -qF "option --out needs a folder name" "$dir/err.txt"
    verdict out-empty-refused $? "exit $status, wrote '$written': $(head -c 300 "$dir/err.txt")"
fi

# 2. Two runs of one set at once, with an earlier set in place.
conc=$dir/concurrent
mkdir -p "$conc"
deck=inputs/tianshengqiao-x1.dat
"$cfrd" --quiet --out "$conc" "$deck" >/dev/null 2>&1
earlier=$(same_files "$conc"/tianshengqiao-x1.out "$conc"/tianshengqiao-x1.h5 \
    "$conc"/tianshengqiao-x1.xmf "$conc"/tianshengqiao-x1-gauges.csv)
"$cfrd" --quiet --out "$conc" "$deck" >"$dir/first.txt" 2>&1 &
first=$!
for _ in $(seq 1 500); do
    [[ -s $conc/tianshengqiao-x1.lock ]] && break
    sleep 0.01
done
start=$(date +%s.%N)
run --quiet --out "$conc" "$deck"
took=$(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.2f}')" \
    "$start" "$(date +%s.%N)")
during=$(same_files "$conc"/tianshengqiao-x1.out "$conc"/tianshengqiao-x1.h5 \
    "$conc"/tianshengqiao-x1.xmf "$conc"/tianshengqiao-x1-gauges.csv)
still=0
kill -0 "$first" 2>/dev/null && still=1
[[ $status -eq 2 ]] &&
    grep -qF "the result set is being written by another run: pid $first on host $host, started " \
        "$dir/err.txt"
verdict second-run-refused $? "exit $status after $took s: $(head -c 300 "$dir/err.txt")"
[[ $still -eq 1 ]]
verdict second-run-refused-at-once $? "the first run had ended before the second was refused ($took s)"
[[ $earlier == "$during" ]]
verdict earlier-set-untouched-while-running $? "the earlier files changed while the first run ran"
wait "$first"
first_status=$?
run --check "$conc"
[[ $first_status -eq 0 && $status -eq 0 && ! -e $conc/tianshengqiao-x1.lock ]] &&
    grep -q "tianshengqiao-x1: whole: run " "$dir/out.txt"
verdict first-run-whole $? "first run exit $first_status; --check exit $status: $(cat "$dir/out.txt" "$dir/err.txt" | head -c 400)"

# 3. Locks: stale (a pid that has ended, on this host), another host's, removed on every end.
locks=$dir/locks
mkdir -p "$locks"
cp inputs/example.dat "$locks/ex.dat"
true &
dead=$!
wait "$dead"
printf 'cfrd result-set lock\nrun_id 20000101T000000-0000000000000000\npid %s\nhost %s\nstarted 2000-01-01T00:00:00+00:00\nstart_ticks 1\ndeck %s\n' \
    "$dead" "$host" "$locks/ex.dat" >"$locks/ex.lock"
run --quiet "$locks/ex.dat"
[[ $status -eq 0 && ! -e $locks/ex.lock && -s $locks/ex.h5 ]] &&
    grep -qF "warning: $locks/ex.dat: took over the stale lock $locks/ex.lock of pid $dead on host $host" "$dir/err.txt"
verdict stale-lock-taken-over $? "exit $status: $(head -c 300 "$dir/err.txt")"
printf 'cfrd result-set lock\nrun_id 20000101T000000-0000000000000000\npid %s\nhost %s\nstarted 2000-01-01T00:00:00+00:00\nstart_ticks 1\ndeck %s\n' \
    "$dead" "not-$host" "$locks/ex.dat" >"$locks/ex.lock"
cp "$locks/ex.lock" "$locks/lock.before"
before=$(same_files "$locks"/ex.out "$locks"/ex.h5 "$locks"/ex.xmf)
run --quiet "$locks/ex.dat"
[[ $status -eq 2 && $before == "$(same_files "$locks"/ex.out "$locks"/ex.h5 "$locks"/ex.xmf)" ]] &&
    cmp -s "$locks/ex.lock" "$locks/lock.before" &&
    grep -qF "pid $dead on host not-$host" "$dir/err.txt"
verdict other-host-lock-refused $? "exit $status: $(head -c 300 "$dir/err.txt")"
rm -f "$locks/ex.lock" "$locks/lock.before"
# A failed analysis (the second square floats: singular at stage 2) releases its lock.
cat >"$locks/float.dat" <<'CARDS'
TITLE     two squares, the second floating
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
    1    2    1    1    1
LOADS
GRAVITY
STAGES
FILL      A             1
FILL      B             1
END
CARDS
run --quiet "$locks/float.dat"
[[ $status -eq 1 && ! -e $locks/float.lock && -e $locks/float.incomplete.h5 ]]
verdict lock-removed-after-failure $? "exit $status, lock left: $(ls "$locks")"
# SIGTERM: the run stops, keeps its stages, and releases the lock.
"$cfrd" --out "$locks" inputs/tianshengqiao-x1.dat >"$dir/term.txt" 2>&1 &
pid=$!
for _ in $(seq 1 1000); do
    grep -q "stage 2/" "$dir/term.txt" && break
    sleep 0.01
done
kill -TERM "$pid"
wait "$pid"
term_status=$?
[[ $term_status -eq 143 && ! -e $locks/tianshengqiao-x1.lock && -e $locks/tianshengqiao-x1.incomplete.h5 ]]
verdict lock-removed-after-sigterm $? "exit $term_status: $(ls "$locks")"
run --check "$locks/tianshengqiao-x1.incomplete.h5"
[[ $status -eq 0 ]] && grep -q "tianshengqiao-x1.incomplete: whole: .*incomplete: " "$dir/out.txt"
verdict incomplete-set-whole $? "exit $status: $(cat "$dir/out.txt" "$dir/err.txt" | head -c 300)"

# 4. One run id in every file of a set; the deck's SHA-256; the files listed.
ids=$dir/ids
mkdir -p "$ids"
cp inputs/tianshengqiao-x1-joint.dat "$ids/joint.dat"
"$cfrd" --quiet --legacy-listing "$ids/joint.dat" >/dev/null 2>&1
run_id=$(h5attr "$ids/joint.h5" run_id)
ok=1
[[ $run_id =~ ^[0-9]{8}T[0-9]{6}-[0-9a-f]{16}$ ]] || ok=0
for f in joint.out joint.lst; do grep -qx " RUN ID $run_id" "$ids/$f" || ok=0; done
grep -qx "<!-- cfrd run_id $run_id -->" "$ids/joint.xmf" || ok=0
for f in joint-gauges.csv joint-interface.csv joint-openings.csv joint-slab.csv; do
    [[ $(head -1 "$ids/$f") == "# cfrd run_id $run_id" ]] || ok=0
done
verdict run-id-in-every-file $((1 - ok)) "run id '$run_id' missing somewhere"
[[ $(h5attr "$ids/joint.h5" deck_sha256) == "$(sha256sum "$ids/joint.dat" | cut -c1-64)" ]]
verdict deck-sha256 $? "$(h5attr "$ids/joint.h5" deck_sha256) against sha256sum"
listed=$(h5attr "$ids/joint.h5" set_files | sort)
present=$(cd "$ids" && ls joint.* joint-* | grep -v '\.dat$' | sort)
[[ $listed == "$present" ]]
verdict set-files-listed $? "listed: $listed; present: $present"

# 5. All or none at the end; a file of an earlier run that this one does not write.
ren=$dir/rename
mkdir -p "$ren"
cp inputs/tianshengqiao-x1.dat "$ren/dam.dat"
"$cfrd" --quiet "$ren/dam.dat" >/dev/null 2>&1
rm "$ren/dam-gauges.csv"
mkdir -p "$ren/dam-gauges.csv/in-the-way"
before=$(same_files "$ren"/dam.out "$ren"/dam.h5 "$ren"/dam.xmf)
run --quiet "$ren/dam.dat"
after=$(same_files "$ren"/dam.out "$ren"/dam.h5 "$ren"/dam.xmf)
left=$(cd "$ren" && ls | grep -E '\.(part|prev|lock)$')
[[ $status -eq 1 && $before == "$after" && -z $left ]] && grep -qF "cannot rename" "$dir/err.txt"
verdict failed-rename-keeps-earlier-set $? "exit $status; left: $left; $(head -c 300 "$dir/err.txt")"
rm -rf "$ren/dam-gauges.csv"
"$cfrd" --quiet --legacy-listing "$ren/dam.dat" >/dev/null 2>&1
"$cfrd" --quiet "$ren/dam.dat" >/dev/null 2>&1
run --check "$ren"
[[ ! -e $ren/dam.lst && $status -eq 0 ]]
verdict earlier-companion-removed $? "dam.lst: $(ls "$ren"); --check exit $status: $(head -c 300 "$dir/out.txt")"

# 6. cfrd --check on a mixed set, a changed deck, nothing to check.
mix=$dir/mixed
mkdir -p "$mix/a" "$mix/b"
cp inputs/example.dat "$mix/a/ex.dat"
"$cfrd" --quiet "$mix/a/ex.dat" >/dev/null 2>&1
"$cfrd" --quiet --out "$mix/b" "$mix/a/ex.dat" >/dev/null 2>&1
run --check "$mix/a/ex.h5"
verdict check-whole $status "exit $status: $(cat "$dir/out.txt" "$dir/err.txt" | head -c 300)"
cp "$mix/b/ex.out" "$mix/a/ex.out"      # the listing of another run of the same deck
run --check "$mix/a"
[[ $status -eq 1 ]] && grep -q "ex: MIXED: ex.out is of run $(h5attr "$mix/b/ex.h5" run_id), ex.h5 of run $(h5attr "$mix/a/ex.h5" run_id)" "$dir/out.txt"
verdict check-mixed $? "exit $status: $(cat "$dir/out.txt" "$dir/err.txt" | head -c 400)"
echo "* one more comment card" >>"$mix/a/ex.dat"
run --check "$mix/b"
[[ $status -eq 1 ]] && grep -q "ex: DECK CHANGED: the deck .*ex.dat has changed since the run" "$dir/out.txt"
verdict check-deck-changed $? "exit $status: $(cat "$dir/out.txt" "$dir/err.txt" | head -c 400)"
mkdir -p "$mix/empty"
run --check "$mix/empty"
verdict check-no-set $([[ $status -eq 2 ]]; echo $?) "exit $status: $(head -c 300 "$dir/err.txt")"
run --check "$mix/no-such.h5"
verdict check-bad-path $([[ $status -eq 2 ]]; echo $?) "exit $status: $(head -c 300 "$dir/err.txt")"
exit 0
