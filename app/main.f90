!> The command line: parses options, and for each deck calls the reader, the analysis and the
!> writers. The only place where an error_t becomes an exit status.
program cfrd_main
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
    use cfrd_error, only: error_t, fatal_error, error_status, usage_error, io_error
    use cfrd_strings, only: to_text
    use cfrd_version, only: cfrd_version_string
    use cfrd_model, only: model_t
    use cfrd_results, only: results_t, stage_result_t
    use cfrd_deck, only: read_deck
    use cfrd_stage_driver, only: run_analysis
    use cfrd_listing, only: write_summary
    use cfrd_run_output, only: run_output_t, begin_output, add_stage, finish_output, &
                               keep_incomplete, discard_output
    use cfrd_files, only: base_name, strip_extension, make_directories, is_directory
    use cfrd_memory, only: tune_allocator
    use cfrd_signals, only: catch_termination, termination_signal, signal_name
    implicit none

    type :: options_t
        logical :: check_only = .false.
        logical :: quiet = .false.
        logical :: legacy_listing = .false.   !! also DECK.lst, the legacy-style tables
        character(len=:), allocatable :: out_dir
    end type options_t

    !> The deck being run and its result files. They live here, not in run_deck, because
    !> the stage driver's progress callback (stream_stage) takes no context of its own:
    !> each stage is written to the files as soon as it is done (docs/results.md).
    type :: current_run_t
        type(model_t) :: model
        type(run_output_t) :: output
        type(error_t), allocatable :: write_error   !! the first failure to write a stage
    end type current_run_t

    type(options_t) :: options
    type(current_run_t) :: current
    character(len=:), allocatable :: decks(:)
    type(error_t), allocatable :: error
    integer :: i, status, worst

    call tune_allocator()
    call parse_command_line(options, decks, error)
    if (.not. allocated(error)) call check_result_names(options, decks, error)
    if (.not. allocated(error) .and. allocated(options%out_dir) .and. &
        .not. options%check_only) call make_directories(options%out_dir, error)
    if (allocated(error)) then
        write (error_unit, '(a)') 'cfrd: '//error%message
        write (error_unit, '(a)') "Try 'cfrd --help'."
        call exit(error_status(error))
    end if

    ! SIGTERM and SIGINT stop the run at the end of the stage it is in (stream_stage).
    if (.not. options%check_only) call catch_termination()
    worst = 0
    do i = 1, size(decks)
        call run_deck(trim(decks(i)), options, status)
        worst = max(worst, status)
        if (termination_signal() /= 0) exit
    end do
    ! A signal after the last stage: the results are complete, the status says it came.
    if (termination_signal() /= 0) worst = max(worst, 128 + termination_signal())
    call exit(worst)

contains

    subroutine run_deck(path, options, status)
        character(len=*), intent(in) :: path
        type(options_t), intent(in) :: options
        integer, intent(out) :: status
        type(results_t) :: results
        type(error_t), allocatable :: error
        character(len=:), allocatable :: stem
        integer :: i

        status = 0
        call new_run(current)
        associate (model => current%model)
            call read_deck(path, model, error)
            if (.not. allocated(error)) then
                do i = 1, size(model%warnings)
                    write (error_unit, '(a)') 'cfrd: warning: '//path//': '// &
                        trim(model%warnings(i))
                end do
            end if
            if (.not. allocated(error) .and. options%check_only) then
                if (.not. options%quiet) write (output_unit, '(a,i0,a,i0,a)') path// &
                    ': OK (', model%mesh%nnode, ' nodes, ', model%mesh%nelem, ' elements)'
                return
            end if
            stem = result_stem(options, path)
            ! Each stage goes to the files when it is done; results keeps the last only.
            if (.not. allocated(error)) call begin_output(current%output, stem, model, error, &
                                                         options%legacy_listing)
            if (.not. allocated(error)) then
                call run_analysis(model, results, error, stream_stage, last_only=.true.)
                if (allocated(error)) then
                    ! The analysis failed: keep its completed stages as DECK.incomplete.h5,
                    ! unless writing them failed too.
                    if (allocated(current%write_error)) then
                        call discard_output(current%output)
                    else
                        call report_incomplete(error, stem)
                    end if
                else if (allocated(current%write_error)) then
                    call move_alloc(current%write_error, error)
                    call discard_output(current%output)
                else
                    call finish_output(current%output, model, results%stages(1), &
                                       results%wall_time, error)
                end if
            end if
            if (allocated(error)) then
                write (error_unit, '(a)') 'cfrd: '//error%message
                status = error_status(error)
                return
            end if
            if (.not. options%quiet) then
                call write_summary(output_unit, model, &
                                   current%output%summaries(1:current%output%completed), &
                                   results%stages(1), results%wall_time)
                write (output_unit, '(a)', advance='no') 'Results: '//stem//'.out, '// &
                    stem//'.h5, '//stem//'.xmf'
                if (size(model%gauges) > 0) then
                    write (output_unit, '(a)') ', '//stem//'-gauges.csv'
                else
                    write (output_unit, '(a)') ''
                end if
                if (options%legacy_listing) write (output_unit, '(a)') &
                    'Legacy-style listing: '//stem//'.lst'
            end if
        end associate
    end subroutine run_deck

    !> A fresh run: no model, no files, no error.
    subroutine new_run(run)
        type(current_run_t), intent(out) :: run
    end subroutine new_run

    !> Keep the completed stages of a failed analysis; the analysis error stays the run's
    !> error (a failure to write the incomplete file is reported beside it).
    subroutine report_incomplete(error, stem)
        type(error_t), intent(in) :: error
        character(len=*), intent(in) :: stem
        type(error_t), allocatable :: keep_error
        call keep_incomplete(current%output, current%model, error%message, keep_error)
        if (allocated(keep_error)) then
            write (error_unit, '(a)') 'cfrd: '//keep_error%message
        else if (.not. options%quiet) then
            write (error_unit, '(a,i0,a)') 'cfrd: the ', current%output%completed, &
                ' completed stages are in '//stem//'.incomplete.h5 (complete = 0)'
        end if
    end subroutine report_incomplete

    !> After each stage: write it to the result files, then print its progress line.
    subroutine stream_stage(number, total, stage)
        integer, intent(in) :: number, total
        type(stage_result_t), intent(in) :: stage
        type(error_t), allocatable :: error
        integer :: signal
        if (.not. allocated(current%write_error)) then
            call add_stage(current%output, current%model, number, stage, error)
            if (allocated(error)) call move_alloc(error, current%write_error)
        end if
        ! A termination signal: keep the completed stages as DECK.incomplete.h5, remove the
        ! temporary files, and stop with 128 + the signal's number (130 SIGINT, 143 SIGTERM).
        signal = termination_signal()
        if (signal /= 0 .and. number < total) then
            call fatal_error(error, 'stopped by '//signal_name(signal)//' after stage '// &
                             to_text(number)//' of '//to_text(total), io_error)
            if (allocated(current%write_error)) then
                call discard_output(current%output)
            else
                call report_incomplete(error, current%output%stem)
            end if
            write (error_unit, '(a)') 'cfrd: '//error%message
            call exit(128 + signal)
        end if
        if (options%quiet) return
        write (output_unit, '(a,i0,a,i0,2a,i0,a,i0,a,i0,a,i0,a,es9.2,a,f8.3,a)') '  stage ', &
            number, '/', total, ': ', stage%name//', ', stage%increments, ' increments, ', &
            stage%factorisations, ' factorisations, ', stage%iterations, ' iterations, ', &
            stage%cutbacks, ' cutbacks, residual', stage%max_residual, ',', stage%wall_time, &
            ' s'
        flush (output_unit)
    end subroutine stream_stage

    subroutine parse_command_line(options, decks, error)
        type(options_t), intent(out) :: options
        character(len=:), allocatable, intent(out) :: decks(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=4096) :: arg
        integer :: i, n, ndeck
        logical :: exists
        n = command_argument_count()
        allocate (character(len=4096) :: decks(n))
        ndeck = 0
        i = 0
        do while (i < n)
            i = i + 1
            call get_command_argument(i, arg)
            select case (trim(arg))
            case ('-h', '--help')
                call print_help()
                call exit(0)
            case ('-V', '--version')
                write (output_unit, '(a)') 'cfrd '//cfrd_version_string
                call exit(0)
            case ('--check')
                options%check_only = .true.
            case ('-q', '--quiet')
                options%quiet = .true.
            case ('--legacy-listing')
                options%legacy_listing = .true.
            case ('-o', '--out')
                if (i == n) then
                    call fatal_error(error, 'option '//trim(arg)//' needs a directory', &
                                     usage_error)
                    return
                end if
                i = i + 1
                call get_command_argument(i, arg)
                options%out_dir = trim(arg)
                ! An unset $OUT in a job script: never the root of the file system.
                if (len(options%out_dir) == 0) then
                    call fatal_error(error, 'option --out needs a folder name (found an '// &
                                     'empty one)', usage_error)
                    return
                end if
                ! A file of that name: the results cannot go into it.
                if (.not. is_directory(options%out_dir)) then
                    inquire (file=options%out_dir, exist=exists)
                    if (exists) then
                        call fatal_error(error, 'option --out names the file '// &
                                         options%out_dir//', not a folder', usage_error)
                        return
                    end if
                end if
            case default
                if (arg(1:1) == '-') then
                    call fatal_error(error, "unknown option '"//trim(arg)//"'", usage_error)
                    return
                end if
                ndeck = ndeck + 1
                decks(ndeck) = arg
            end select
        end do
        if (ndeck == 0) then
            call fatal_error(error, 'no deck given', usage_error)
            return
        end if
        decks = decks(1:ndeck)
    end subroutine parse_command_line

    !> Two decks whose results would have the same names (the same base name into one --out
    !> folder, or one deck listed twice) are refused before anything runs.
    subroutine check_result_names(options, decks, error)
        type(options_t), intent(in) :: options
        character(len=*), intent(in) :: decks(:)
        type(error_t), allocatable, intent(out) :: error
        integer :: i, j
        if (options%check_only) return
        do i = 2, size(decks)
            do j = 1, i - 1
                if (result_stem(options, decks(i)) == result_stem(options, decks(j))) then
                    call fatal_error(error, 'decks '//trim(decks(j))//' and '// &
                                     trim(decks(i))//' would both write their results to '// &
                                     result_stem(options, decks(i))//'.*: run them into '// &
                                     'different --out folders, or rename one', usage_error)
                    return
                end if
            end do
        end do
    end subroutine check_result_names

    !> Where a deck's results go: DECK without its extension, or DIR/its base name.
    function result_stem(options, path) result(stem)
        type(options_t), intent(in) :: options
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: stem
        if (allocated(options%out_dir)) then
            stem = options%out_dir//'/'//strip_extension(base_name(trim(path)))
        else
            stem = strip_extension(trim(path))
        end if
    end function result_stem

    subroutine print_help()
        write (output_unit, '(a)') &
            'Usage: cfrd [options] DECK [DECK ...]', &
            '', &
            'Runs each card deck (docs/cards.md) and writes DECK.out (listing), DECK.h5', &
            '(results, docs/results.md) and DECK.xmf (for ParaView) beside it, or in', &
            '--out DIR. A failed analysis keeps its completed stages in', &
            'DECK.incomplete.h5 and leaves earlier results untouched.', &
            '', &
            'Options:', &
            '  --check       read and validate the decks only', &
            '  --out DIR     write results into DIR (made if missing)', &
            '  --quiet       print nothing but errors', &
            '  --legacy-listing', &
            '                also write DECK.lst: the legacy codes'' per-layer tables of', &
            '                node displacements and element stresses and stress levels', &
            '  --version     print the version', &
            '  --help        print this help', &
            '', &
            'Exit status: 0 all decks ran, 1 a numerical or file failure, 2 bad input or usage.'
    end subroutine print_help
end program cfrd_main
