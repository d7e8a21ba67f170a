!> The result files of one run, written while the analysis runs (docs/results.md,
!> "Streaming and temporary names"): begin_output opens DECK.h5.part and the interface CSV
!> files before the first stage; add_stage writes each stage to them (and flushes the HDF5
!> file) and keeps only its summary; at the end finish_output writes the listing, the gauge
!> and opening CSV files and DECK.xmf from the summaries and the last stage, sets
!> `complete` = 1 and renames every file into place. After a failed analysis
!> keep_incomplete closes the HDF5 file with `complete` = 0 and the reason, and renames it
!> DECK.incomplete.h5 (with DECK.incomplete.xmf); after a failed write discard_output
!> removes the temporary files. Either way the results of an earlier run are untouched.
!> result_stem names a deck's result files; check_result_names refuses, before any run, a
!> list of decks two of which would write the same files.
module cfrd_run_output
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, usage_error
    use cfrd_clock, only: wall_seconds
    use cfrd_model, only: model_t
    use cfrd_results, only: stage_result_t
    use cfrd_stage_summary, only: stage_summary_t, summarise
    use cfrd_hdf5, only: results_file_t, results_format_t, open_results_h5, write_stage_h5, &
                         close_results_h5
    use cfrd_xdmf, only: write_xdmf
    use cfrd_listing, only: write_listing, write_gauge_csv
    use cfrd_interface_io, only: interface_csv_t, open_interface_csv, append_interface_csv, &
                                 close_interface_csv, write_openings_csv, has_interfaces, &
                                 has_slab, has_contact, has_openings
    use cfrd_legacy_listing, only: open_legacy_listing, append_legacy_stage, &
                                   close_legacy_listing
    use cfrd_files, only: move_file, delete_file, base_name, strip_extension, resolved_path
    implicit none
    private

    public :: run_output_t, begin_output, add_stage, finish_output, keep_incomplete
    public :: discard_output, result_stem, check_result_names

    !> Suffix of the files being written; of the results file a failed run leaves.
    character(len=*), parameter :: part = '.part', incomplete = '.incomplete'
    !> Every file a run may write after the stem (DECK.out, DECK.h5, ...).
    character(len=*), parameter :: endings(9) = [character(len=14) :: '.out', '.h5', '.xmf', &
                                                 '-gauges.csv', '-interface.csv', &
                                                 '-openings.csv', '-slab.csv', '-contact.csv', &
                                                 '.lst']

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

    !> Open the temporary files of a run of `model` whose results go to `stem`.* .
    subroutine begin_output(out, stem, model, error, legacy_listing, format)
        type(run_output_t), intent(out) :: out
        character(len=*), intent(in) :: stem
        type(model_t), intent(in) :: model
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in) :: legacy_listing    !! also DECK.lst (cfrd --legacy-listing)
        !> how the HDF5 file stores its values (cfrd --compress, --float32)
        type(results_format_t), intent(in), optional :: format
        out%stem = stem
        out%t_start = wall_seconds()
        allocate (out%summaries(size(model%stages)))
        call open_results_h5(out%h5, stem//'.h5'//part, model, error, format)
        if (.not. allocated(error)) call open_interface_csv(out%csv, stem, part, model, error)
        if (.not. allocated(error) .and. legacy_listing) &
            call open_legacy_listing(stem//'.lst'//part, model, out%legacy_unit, error)
        if (allocated(error)) call discard_output(out)
    end subroutine begin_output

    !> Stage `number` is done: write it to the HDF5 and CSV files, keep its summary.
    subroutine add_stage(out, model, number, stage, error)
        type(run_output_t), intent(inout) :: out
        type(model_t), intent(in) :: model
        integer, intent(in) :: number
        type(stage_result_t), intent(in) :: stage
        type(error_t), allocatable, intent(out) :: error
        call write_stage_h5(out%h5, number, stage, error)
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
    !> last stage's full results), mark the HDF5 file complete and rename all into place.
    !> Removes DECK.incomplete.* left by an earlier failed run. On an error the temporary
    !> files are removed and the earlier results stay as they were.
    subroutine finish_output(out, model, last, wall_time, error)
        type(run_output_t), intent(inout) :: out
        type(model_t), intent(in) :: model
        type(stage_result_t), intent(in) :: last
        real(dp), intent(in) :: wall_time      !! s, the analysis
        type(error_t), allocatable, intent(out) :: error
        logical :: written(size(endings))
        integer :: k
        associate (stem => out%stem, summaries => out%summaries(1:out%completed))
            written = [.true., .true., .true., .false., has_interfaces(model), &
                       has_openings(model), has_slab(model), has_contact(model), &
                       out%legacy_unit /= 0]
            if (allocated(model%gauges)) written(4) = size(model%gauges) > 0
            call close_interface_csv(out%csv, error)
            if (.not. allocated(error) .and. written(9)) then
                call close_legacy_listing(out%legacy_unit, stem//'.lst'//part, error)
                out%legacy_unit = 0
            end if
            if (.not. allocated(error)) &
                call close_results_h5(out%h5, .true., error, wall_time=wall_time)
            if (.not. allocated(error)) &
                call write_listing(stem//'.out'//part, model, summaries, last, wall_time, error)
            if (.not. allocated(error)) call write_xdmf(stem//'.xmf'//part, &
                                                        base_name(stem)//'.h5', model, &
                                                        out%completed, error, &
                                                        out%h5%format%single)
            if (.not. allocated(error) .and. written(4)) &
                call write_gauge_csv(stem//'-gauges.csv'//part, model, summaries, error)
            if (.not. allocated(error) .and. written(6)) &
                call write_openings_csv(stem//'-openings.csv'//part, model, summaries, error)
            do k = 1, size(endings)
                if (.not. allocated(error) .and. written(k)) &
                    call move_file(stem//trim(endings(k))//part, stem//trim(endings(k)), error)
            end do
            if (allocated(error)) then
                call discard_output(out)
                return
            end if
            call delete_file(stem//incomplete//'.h5')
            call delete_file(stem//incomplete//'.xmf')
        end associate
    end subroutine finish_output

    !> The analysis failed (`failure` says why): keep the completed stages as
    !> DECK.incomplete.h5 (root attributes complete = 0, failure) with DECK.incomplete.xmf
    !> when a stage was completed, and remove the other temporary files. On an error
    !> writing these, nothing is kept.
    subroutine keep_incomplete(out, model, failure, error)
        type(run_output_t), intent(inout) :: out
        type(model_t), intent(in) :: model
        character(len=*), intent(in) :: failure
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: stem
        stem = out%stem
        call close_interface_csv(out%csv)
        if (out%legacy_unit /= 0) close (out%legacy_unit)
        out%legacy_unit = 0
        call close_results_h5(out%h5, .false., error, wall_time=wall_seconds() - out%t_start, &
                              failure=failure)
        call delete_file(stem//incomplete//'.xmf')
        if (.not. allocated(error) .and. out%completed > 0) &
            call write_xdmf(stem//incomplete//'.xmf'//part, base_name(stem)//incomplete// &
                            '.h5', model, out%completed, error, out%h5%format%single)
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
