!> The result files of one run, written while the analysis runs (docs/results.md,
!> "Streaming and temporary names"): begin_output opens DECK.h5.part and the interface CSV
!> files before the first stage; add_stage writes each stage to them (and flushes the HDF5
!> file) and keeps only its summary; at the end finish_output writes the listing, the gauge
!> and opening CSV files and DECK.xmf from the summaries and the last stage, sets
!> `complete` = 1 and renames every file into place. After a failed analysis
!> keep_incomplete closes the HDF5 file with `complete` = 0 and the reason, and renames it
!> DECK.incomplete.h5 (with DECK.incomplete.xmf); after a failed write discard_output
!> removes the temporary files. Either way the results of an earlier run are untouched:
!> the renames at the end replace the files of the set all or none (docs/results.md,
!> "Result sets"). Every file carries the run id of `run_identity_t`.
!> result_stem names a deck's result files; check_result_names refuses, before any run, a
!> list of decks two of which would write the same files; check_inputs_kept one whose
!> result files would be one of the decks.
module cfrd_run_output
    use hdf5, only: hid_t
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, usage_error, io_error
    use cfrd_clock, only: wall_seconds
    use cfrd_model, only: model_t
    use cfrd_results, only: stage_result_t
    use cfrd_stage_summary, only: stage_summary_t, summarise
    use cfrd_hdf5, only: results_file_t, results_format_t, open_results_h5, write_stage_h5, &
                         close_results_h5
    use cfrd_xdmf, only: write_xdmf
    use cfrd_h5_state, only: copy_stage
    use cfrd_listing, only: write_listing, write_gauge_csv
    use cfrd_interface_io, only: interface_csv_t, open_interface_csv, append_interface_csv, &
                                 close_interface_csv, write_openings_csv, has_interfaces, &
                                 has_slab, has_contact, has_openings
    use cfrd_pjoint_io, only: has_pjoint, write_pjoint_csv
    use cfrd_legacy_listing, only: open_legacy_listing, append_legacy_stage, &
                                   close_legacy_listing
    use cfrd_files, only: move_file, delete_file, base_name, strip_extension, resolved_path, &
                          path_exists, link_file, canonical_path
    use cfrd_run_identity, only: run_identity_t, text_run_id
    implicit none
    private

    public :: run_output_t, begin_output, add_stage, finish_output, keep_incomplete
    public :: discard_output, result_stem, check_result_names, check_inputs_kept
    public :: set_endings, lock_ending, incomplete_ending

    !> Suffix of the files being written; of the results file a failed run leaves; of a
    !> file being replaced, kept until the whole set is in place; of the set's lock.
    character(len=*), parameter :: part = '.part', incomplete = '.incomplete', &
                                   previous = '.prev', lock_ending = '.lock'
    character(len=*), parameter :: incomplete_ending = incomplete
    !> Every file a run may write after the stem (DECK.out, DECK.h5, ...).
    character(len=*), parameter :: endings(10) = [character(len=14) :: '.out', '.h5', '.xmf', &
                                                  '-gauges.csv', '-interface.csv', &
                                                  '-openings.csv', '-slab.csv', '-contact.csv', &
                                                  '.lst', '-pjoint.csv']
    character(len=*), parameter :: set_endings(*) = endings

    !> The files of a run being written.
    type :: run_output_t
        character(len=:), allocatable :: stem           !! DECK path without .dat
        type(results_file_t) :: h5
        type(interface_csv_t) :: csv
        !> (nstages) one per stage; the first `completed` are filled
        type(stage_summary_t), allocatable :: summaries(:)
        integer :: completed = 0
        integer :: legacy_unit = 0                      !! DECK.lst.part, open (--legacy-listing)
        real(dp) :: t_start = 0.0_dp                    !! s, wall clock at begin_output
        type(run_identity_t) :: identity                !! the run id every file carries
    end type run_output_t

contains

    !> The results of `deck` go to STEM.out, STEM.h5, ...: the deck's path without its
    !> extension, or its name without extension in `out_dir` (cfrd --out).
    function result_stem(deck, out_dir) result(stem)
        character(len=*), intent(in) :: deck
        character(len=*), intent(in), optional :: out_dir
        character(len=:), allocatable :: stem
        if (present(out_dir)) then
            stem = out_dir//'/'//strip_extension(base_name(deck))
        else
            stem = strip_extension(deck)
        end if
    end function result_stem

    !> A usage error naming both decks when two of `decks` would write the same result
    !> files (the second would overwrite the first): the same name into one --out folder,
    !> or, beside the decks, the same folder (however spelt) and name (a.dat, a.txt, a).
    subroutine check_result_names(decks, error, out_dir)
        character(len=*), intent(in) :: decks(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: out_dir
        character(len=4096) :: keys(size(decks))
        character(len=:), allocatable :: deck
        integer :: i, j, slash
        do i = 1, size(decks)
            deck = trim(decks(i))
            if (present(out_dir)) then
                keys(i) = strip_extension(base_name(deck))
            else
                slash = index(deck, '/', back=.true.)
                if (slash == 0) then
                    keys(i) = resolved_path('.')//'/'//strip_extension(deck)
                else
                    keys(i) = resolved_path(deck(:max(slash - 1, 1)))//'/'// &
                              strip_extension(base_name(deck))
                end if
            end if
            do j = 1, i - 1
                if (keys(j) /= keys(i)) cycle
                call fatal_error(error, trim(decks(j))//' and '//deck// &
                                 ' would both write '//result_stem(deck, out_dir)// &
                                 '.h5 (and .out, .xmf): the second would overwrite '// &
                                 'the first; run them into different --out folders', &
                                 usage_error)
                return
            end do
        end do
    end subroutine check_result_names

    !> A usage error naming both when a file that a run of one of `decks` writes, renames
    !> or removes (its result files, their temporary names, DECK.incomplete.*, the lock) is
    !> one of the decks itself: `cp dam.dat dam.out; cfrd dam.out` would replace the deck
    !> by its listing. Names compare after their folders are resolved (however spelt, links
    !> followed), and against each deck's own resolved path. A deck names no other input
    !> file today; one that did would be compared here too.
    subroutine check_inputs_kept(decks, error, out_dir)
        character(len=*), intent(in) :: decks(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: out_dir
        character(len=4096) :: as_given(size(decks)), resolved(size(decks))
        character(len=:), allocatable :: names(:), stem, name
        integer :: i, j, k
        do j = 1, size(decks)
            as_given(j) = canonical_path(trim(decks(j)))
            resolved(j) = resolved_path(trim(decks(j)))
        end do
        do i = 1, size(decks)
            stem = result_stem(trim(decks(i)), out_dir)
            names = set_file_names(stem)
            do k = 1, size(names)
                name = canonical_path(trim(names(k)))
                do j = 1, size(decks)
                    if (name /= trim(as_given(j)) .and. name /= trim(resolved(j))) cycle
                    if (i == j) then
                        call fatal_error(error, trim(decks(i))//': the run would write '// &
                                         trim(names(k))//', which is the deck itself: '// &
                                         'rename the deck (a deck named '//stem//'.dat '// &
                                         'writes '//stem//'.out, .h5, .xmf) or write '// &
                                         'the results elsewhere with --out DIR', &
                                         usage_error)
                    else
                        call fatal_error(error, trim(decks(i))//': the run would write '// &
                                         trim(names(k))//', which is the deck '// &
                                         trim(decks(j))//' given on the same command '// &
                                         'line: rename that deck or write the results '// &
                                         'elsewhere with --out DIR', usage_error)
                    end if
                    return
                end do
            end do
        end do
    end subroutine check_inputs_kept

    !> Every name a run with results at `stem` writes, renames or removes.
    function set_file_names(stem) result(names)
        character(len=*), intent(in) :: stem
        character(len=:), allocatable :: names(:)
        integer :: k, n
        allocate (character(len=len(stem) + len(endings) + len(incomplete) + 8) :: &
                  names(3*size(endings) + 5))
        n = 0
        do k = 1, size(endings)
            names(n + 1) = stem//trim(endings(k))
            names(n + 2) = stem//trim(endings(k))//part
            names(n + 3) = stem//trim(endings(k))//previous
            n = n + 3
        end do
        names(n + 1) = stem//incomplete//'.h5'
        names(n + 2) = stem//incomplete//'.h5'//part
        names(n + 3) = stem//incomplete//'.xmf'
        names(n + 4) = stem//incomplete//'.xmf'//part
        names(n + 5) = stem//lock_ending
    end function set_file_names

    !> Open the temporary files of the run `identity` of `model` whose results go to
    !> `stem`.* .
    subroutine begin_output(out, stem, model, identity, error, legacy_listing, format)
        type(run_output_t), intent(out) :: out
        character(len=*), intent(in) :: stem
        type(model_t), intent(in) :: model
        type(run_identity_t), intent(in) :: identity
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in) :: legacy_listing    !! also DECK.lst (cfrd --legacy-listing)
        !> how the HDF5 file stores its values (cfrd --compress, --float32)
        type(results_format_t), intent(in), optional :: format
        out%stem = stem
        out%t_start = wall_seconds()
        out%identity = identity
        allocate (out%summaries(size(model%stages)))
        call open_results_h5(out%h5, stem//'.h5'//part, model, error, identity, format)
        if (.not. allocated(error)) call open_interface_csv(out%csv, stem, part, model, error, &
                                                            identity%run_id)
        if (.not. allocated(error) .and. legacy_listing) &
            call open_legacy_listing(stem//'.lst'//part, model, out%legacy_unit, error, &
                                     identity%run_id)
        if (allocated(error)) call discard_output(out)
    end subroutine begin_output

    !> Stage `number` is done: write it to the HDF5 and CSV files, keep its summary.
    !> `copy_from`: the stage is the stage of that open results file, which stores its
    !> values as this one does (cfrd --restart): its HDF5 group is copied, not written.
    subroutine add_stage(out, model, number, stage, error, copy_from)
        type(run_output_t), intent(inout) :: out
        type(model_t), intent(in) :: model
        integer, intent(in) :: number
        type(stage_result_t), intent(in) :: stage
        type(error_t), allocatable, intent(out) :: error
        integer(hid_t), intent(in), optional :: copy_from
        if (present(copy_from)) then
            call copy_stage(copy_from, out%h5%file_id, out%h5%stages_id, out%h5%path, &
                            number, error)
            if (.not. allocated(error)) out%h5%stages_written = number
        else
            call write_stage_h5(out%h5, number, stage, error)
        end if
        if (allocated(error)) return
        call append_interface_csv(out%csv, model, number, stage, error)
        if (allocated(error)) return
        if (out%legacy_unit /= 0) then
            call append_legacy_stage(out%legacy_unit, out%stem//'.lst'//part, model, number, &
                                     stage, error)
            if (allocated(error)) return
        end if
        out%summaries(number) = summarise(model, stage)
        out%completed = number
    end subroutine add_stage

    !> Every stage is done: write the remaining files from the summaries and `last` (the
    !> last stage's full results), mark the HDF5 file complete and rename all into place,
    !> all or none (replace_set). Removes DECK.incomplete.* left by an earlier failed run,
    !> and the files of an earlier run of the set that this one does not write (a gauge
    !> CSV of a deck that has no gauges now: files with a cfrd run id only). On an error
    !> the temporary files are removed and the earlier results stay as they were.
    subroutine finish_output(out, model, last, wall_time, error)
        type(run_output_t), intent(inout) :: out
        type(model_t), intent(in) :: model
        type(stage_result_t), intent(in) :: last
        real(dp), intent(in) :: wall_time      !! s, the analysis
        type(error_t), allocatable, intent(out) :: error
        logical :: written(size(endings))
        character(len=:), allocatable :: files
        integer :: k
        associate (stem => out%stem, summaries => out%summaries(1:out%completed), &
                   run_id => out%identity%run_id)
            written = [.true., .true., .true., .false., has_interfaces(model), &
                       has_openings(model), has_slab(model), has_contact(model), &
                       out%legacy_unit /= 0, has_pjoint(model)]
            if (allocated(model%gauges)) written(4) = size(model%gauges) > 0
            files = ''
            do k = 1, size(endings)
                if (written(k)) files = files//base_name(stem)//trim(endings(k))//new_line('a')
            end do
            call close_interface_csv(out%csv, error)
            if (.not. allocated(error) .and. written(9)) then
                call close_legacy_listing(out%legacy_unit, stem//'.lst'//part, error)
                out%legacy_unit = 0
            end if
            if (.not. allocated(error)) &
                call close_results_h5(out%h5, .true., error, wall_time=wall_time, &
                                      set_files=files(:len(files) - 1))
            if (.not. allocated(error)) &
                call write_listing(stem//'.out'//part, model, summaries, last, wall_time, error, &
                                   out%identity)
            if (.not. allocated(error)) call write_xdmf(stem//'.xmf'//part, &
                                                        base_name(stem)//'.h5', model, &
                                                        out%completed, error, run_id, &
                                                        out%h5%format%single, &
                                                        out%h5%format%full)
            if (.not. allocated(error) .and. written(4)) &
                call write_gauge_csv(stem//'-gauges.csv'//part, model, summaries, error, run_id)
            if (.not. allocated(error) .and. written(6)) &
                call write_openings_csv(stem//'-openings.csv'//part, model, summaries, error, &
                                        run_id)
            if (.not. allocated(error) .and. written(10)) &
                call write_pjoint_csv(stem//'-pjoint.csv'//part, model, summaries, error, run_id)
            if (.not. allocated(error)) call replace_set(stem, written, error)
            if (allocated(error)) then
                call discard_output(out)
                return
            end if
            call delete_file(stem//incomplete//'.h5')
            call delete_file(stem//incomplete//'.xmf')
            ! A file of an earlier run of this set that this run does not write would
            ! otherwise stay beside the new ones as if it belonged to them.
            do k = 1, size(endings)
                if (written(k)) cycle
                if (len(text_run_id(stem//trim(endings(k)))) > 0) &
                    call delete_file(stem//trim(endings(k)))
            end do
        end associate
    end subroutine finish_output

    !> Rename each written STEM.ENDING.part to STEM.ENDING, all or none: the files being
    !> replaced are kept under a second name (a hard link, STEM.ENDING.prev) until every
    !> rename has succeeded, and put back if one fails, so that a failure here leaves the
    !> earlier set as it was rather than half replaced. (Where hard links cannot be made,
    !> a failed rename leaves the new file in place, and `cfrd --check` says so.)
    subroutine replace_set(stem, written, error)
        character(len=*), intent(in) :: stem
        logical, intent(in) :: written(:)
        type(error_t), allocatable, intent(out) :: error
        logical :: existed(size(endings)), kept(size(endings))
        type(error_t), allocatable :: link_error, undo_error
        character(len=:), allocatable :: target
        integer :: k, failed
        existed = .false.
        kept = .false.
        do k = 1, size(endings)
            if (.not. written(k)) cycle
            target = stem//trim(endings(k))
            existed(k) = path_exists(target)
            if (.not. existed(k)) cycle
            call delete_file(target//previous)
            call link_file(target, target//previous, link_error)
            kept(k) = .not. allocated(link_error)
        end do
        failed = 0
        do k = 1, size(endings)
            if (.not. written(k)) cycle
            call move_file(stem//trim(endings(k))//part, stem//trim(endings(k)), error)
            if (allocated(error)) then
                failed = k
                exit
            end if
        end do
        do k = 1, size(endings)
            if (.not. written(k)) cycle
            target = stem//trim(endings(k))
            if (failed > 0 .and. k < failed) then
                ! Undo: the earlier file back, or no file where there was none.
                if (kept(k)) then
                    call move_file(target//previous, target, undo_error)
                else if (.not. existed(k)) then
                    call delete_file(target)
                end if
            end if
            call delete_file(target//previous)
        end do
        if (failed > 0) error%message = error%message//'; the earlier results are kept'
    end subroutine replace_set

    !> The analysis failed (`failure` says why): keep the completed stages as
    !> DECK.incomplete.h5 (root attributes complete = 0, failure) with DECK.incomplete.xmf
    !> when a stage was completed, and remove the other temporary files. On an error
    !> writing these, nothing is kept.
    subroutine keep_incomplete(out, model, failure, error)
        type(run_output_t), intent(inout) :: out
        type(model_t), intent(in) :: model
        character(len=*), intent(in) :: failure
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: stem, files
        stem = out%stem
        call close_interface_csv(out%csv)
        if (out%legacy_unit /= 0) close (out%legacy_unit)
        out%legacy_unit = 0
        files = base_name(stem)//incomplete//'.h5'
        if (out%completed > 0) files = files//new_line('a')//base_name(stem)//incomplete//'.xmf'
        call close_results_h5(out%h5, .false., error, wall_time=wall_seconds() - out%t_start, &
                              failure=failure, set_files=files)
        call delete_file(stem//incomplete//'.xmf')
        if (.not. allocated(error) .and. out%completed > 0) &
            call write_xdmf(stem//incomplete//'.xmf'//part, base_name(stem)//incomplete// &
                            '.h5', model, out%completed, error, out%identity%run_id, &
                            out%h5%format%single, out%h5%format%full)
        if (.not. allocated(error)) &
            call move_file(stem//'.h5'//part, stem//incomplete//'.h5', error)
        if (.not. allocated(error) .and. out%completed > 0) &
            call move_file(stem//incomplete//'.xmf'//part, stem//incomplete//'.xmf', error)
        call discard_output(out)
        if (allocated(error)) call delete_file(stem//incomplete//'.xmf'//part)
    end subroutine keep_incomplete

    !> Close whatever is open and remove every temporary file of the run.
    subroutine discard_output(out)
        type(run_output_t), intent(inout) :: out
        integer :: k
        call close_interface_csv(out%csv)
        if (out%legacy_unit /= 0) close (out%legacy_unit)
        out%legacy_unit = 0
        call close_results_h5(out%h5, .false.)
        do k = 1, size(endings)
            call delete_file(out%stem//trim(endings(k))//part)
        end do
    end subroutine discard_output
end module cfrd_run_output
