!> The command line: parses options, and for each deck calls the reader, the analysis and the
!> writers. The only place where an error_t becomes an exit status.
program cfrd_main
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
    use cfrd_error, only: error_t, fatal_error, error_status, usage_error, interrupt_error, &
                          terminate_error
    use cfrd_version, only: cfrd_version_string
    use cfrd_model, only: model_t
    use cfrd_results, only: results_t, stage_result_t
    use cfrd_deck, only: read_deck
    use cfrd_stage_driver, only: run_analysis
    use cfrd_listing, only: write_summary
    use cfrd_run_output, only: run_output_t, begin_output, finish_output, &
                               keep_incomplete, discard_output, result_stem, &
                               check_result_names, check_inputs_kept, lock_ending
    use cfrd_run_identity, only: run_identity_t, new_run_identity
    use cfrd_result_lock, only: result_lock_t, acquire_lock, release_lock
    use cfrd_set_check, only: check_results, is_results_path
    use cfrd_files, only: path_exists, is_directory, make_directories
    use cfrd_signals, only: catch_stop_signals, stop_signal, signal_name
    use cfrd_strings, only: to_text
    use cfrd_memory, only: tune_allocator
    use cfrd_hdf5, only: results_format_t
    use cfrd_stage_writer, only: write_stage_behind, wait_stage_writes
    use cfrd_blas_threads, only: set_blas_threads
    use cfrd_omp_threads, only: set_omp_threads
    use cfrd_linear_solver, only: linear_solver_auto, linear_solver_cholmod, &
                                  linear_solver_umfpack
    use cfrd_restart, only: restart_t, open_restart, restart_model, restart_stem, &
                            read_restart_stage, close_restart
    implicit none

    type :: options_t
        logical :: check_only = .false.
        logical :: quiet = .false.
        logical :: legacy_listing = .false.   !! also DECK.lst, the legacy-style tables
        type(results_format_t) :: format      !! --compress, --float32, --results
        character(len=:), allocatable :: out_dir
        !> with --check: the folders and results files (.h5) whose result sets to check
        character(len=:), allocatable :: result_paths(:)
        !> --restart RESULTS.h5 [--from-stage K]: the results file to continue from stage K
        !> (0: its last completed stage)
        character(len=:), allocatable :: restart
        integer :: from_stage = 0
        !> --threads N: the OpenMP threads of the element loops (0: OMP_NUM_THREADS, else 1)
        integer :: threads = 0
        !> --linear-solver auto|cholmod|umfpack (cfrd_linear_solver)
        integer :: linear_solver = linear_solver_auto
    end type options_t

    !> The deck being run and its result files. They live here, not in run_deck, because
    !> the stage driver's progress callback (stream_stage) takes no context of its own:
    !> each stage is written to the files as soon as it is done (docs/results.md).
    type :: current_run_t
        type(model_t) :: model
        type(run_output_t) :: output
        type(error_t), allocatable :: write_error   !! the first failure to write a stage
        type(run_identity_t) :: identity            !! run id, the deck's SHA-256
        type(result_lock_t) :: lock                 !! DECK.lock, held while the run writes
        type(restart_t) :: source                   !! --restart: the file continued from
    end type current_run_t

    type(options_t) :: options
    !> (a target: the stage writer keeps pointers to its output and model while it writes)
    type(current_run_t), target :: current
    character(len=:), allocatable :: decks(:)
    type(error_t), allocatable :: error
    integer :: i, status, worst

    call tune_allocator()
    i = set_blas_threads()
    call parse_command_line(options, decks, error)
    if (.not. allocated(error)) call check_outputs(options, decks, error)
    if (.not. allocated(error)) i = set_omp_threads(options%threads)
    if (allocated(error)) then
        write (error_unit, '(a)') 'cfrd: '//error%message
        if (error%category == usage_error) write (error_unit, '(a)') "Try 'cfrd --help'."
        call exit(error_status(error))
    end if

    worst = 0
    if (options%check_only) call check_result_sets(options%result_paths, worst)

    ! SIGINT / SIGTERM stop a run between increments, keeping its completed stages
    ! (docs/results.md, "Stopped runs"); the remaining decks are not run.
    call catch_stop_signals()
    do i = 1, size(decks)
        call run_deck(trim(decks(i)), options, status)
        ! However the run ended (short of a kill), its result set is free again.
        call release_lock(current%lock)
        worst = max(worst, status)
        if (stop_signal() /= 0) then
            call report_stop(decks, i, status)
            call exit(128 + stop_signal())
        end if
    end do
    call exit(worst)

contains

    subroutine run_deck(path, options, status)
        character(len=*), intent(in) :: path
        type(options_t), intent(in) :: options
        integer, intent(out) :: status
        type(results_t) :: results
        type(error_t), allocatable :: error
        character(len=:), allocatable :: stem, warning, who
        integer :: i
        logical :: restart

        status = 0
        call new_run(current)
        restart = allocated(options%restart)
        who = path
        if (restart .and. len(path) == 0) who = options%restart
        associate (model => current%model)
            if (restart) then
                ! cfrd --restart: the stored deck (no DECK given: path = '') or DECK
                call open_restart(options%restart, options%from_stage, current%source, &
                                  error)
                if (.not. allocated(error)) call restart_model(current%source, path, model, &
                                                               error)
            else
                call read_deck(path, model, error)
            end if
            if (.not. allocated(error)) then
                model%linear_solver = options%linear_solver
                do i = 1, size(model%warnings)
                    write (error_unit, '(a)') 'cfrd: warning: '//who//': '// &
                        trim(model%warnings(i))
                end do
            end if
            if (.not. allocated(error) .and. options%check_only) then
                if (.not. options%quiet) write (output_unit, '(a,i0,a,i0,a)') path// &
                    ': OK (', model%mesh%nnode, ' nodes, ', model%mesh%nelem, ' elements)'
                return
            end if
            if (restart .and. len(path) == 0) then
                stem = restart_stem(current%source)
                if (allocated(options%out_dir)) stem = restart_stem(current%source, &
                                                                    options%out_dir)
            else if (allocated(options%out_dir)) then
                stem = result_stem(path, options%out_dir)
            else
                stem = result_stem(path)
            end if
            ! The run's identity, and the lock on its result set before any file is written
            ! (a second run of the same set is refused here).
            if (allocated(error)) then
                continue
            else if (restart .and. len(path) == 0) then
                call new_run_identity(current%source%deck_path, current%identity, error, &
                                      current%source%deck_sha256)
            else
                call new_run_identity(path, current%identity, error)
            end if
            if (.not. allocated(error)) then
                call acquire_lock(current%lock, stem//lock_ending, current%identity, error, &
                                  warning)
                if (allocated(warning)) write (error_unit, '(a)') 'cfrd: warning: '//who// &
                    ': '//warning
                if (allocated(error)) error%message = who//': '//error%message
            end if
            ! Each stage goes to the files when it is done; results keeps the last only.
            if (.not. allocated(error)) call begin_output(current%output, stem, model, &
                                                         current%identity, error, &
                                                         options%legacy_listing, options%format)
            if (.not. allocated(error)) then
                if (restart) then
                    call run_analysis(model, results, error, stream_stage, last_only=.true., &
                                      stored=stored_stage, &
                                      from_stage=current%source%from_stage)
                else
                    call run_analysis(model, results, error, stream_stage, last_only=.true.)
                end if
                ! the last stage's write done, and the first write error, if any, taken
                call wait_stage_writes(current%write_error)
                ! the file continued from is read; it may be replaced now
                call close_restart(current%source)
                if (allocated(error)) then
                    ! The analysis failed: keep its completed stages as DECK.incomplete.h5,
                    ! unless writing them failed too.
                    if (allocated(current%write_error)) then
                        call discard_output(current%output)
                    else
                        call report_incomplete(error, stem)
                    end if
                    if (any(error%category == [interrupt_error, terminate_error])) &
                        error%message = who//': '//error%message//'; '// &
                                        last_stage_text(model, current%output%completed)
                else if (allocated(current%write_error)) then
                    call move_alloc(current%write_error, error)
                    call discard_output(current%output)
                else
                    call finish_output(current%output, model, results%stages(1), &
                                       results%wall_time, error)
                end if
            end if
            call close_restart(current%source)
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

    !> 'last completed stage: 3/12 (layer 3)', or 'no stage completed'.
    function last_stage_text(model, completed) result(text)
        type(model_t), intent(in) :: model
        integer, intent(in) :: completed
        character(len=:), allocatable :: text
        if (completed == 0) then
            text = 'no stage completed'
        else
            text = 'last completed stage: '//to_text(completed)//'/'// &
                   to_text(size(model%stages))//' ('//trim(model%stages(completed)%label)//')'
        end if
    end function last_stage_text

    !> A stop signal came while deck `i` ran (its own message is printed if the signal
    !> stopped its analysis): say whether it finished anyway and which decks are not run.
    subroutine report_stop(decks, i, status)
        character(len=*), intent(in) :: decks(:)
        integer, intent(in) :: i, status
        character(len=:), allocatable :: name
        integer :: k
        name = signal_name(stop_signal())
        if (status < 128) write (error_unit, '(a)') 'cfrd: '//name//' came after '// &
            trim(decks(i))//' had completed its analysis: it ran to its end'
        if (i < size(decks)) then
            write (error_unit, '(a)', advance='no') 'cfrd: stopped by '//name//'; not run:'
            do k = i + 1, size(decks)
                write (error_unit, '(a)', advance='no') ' '//trim(decks(k))
            end do
            write (error_unit, '(a)') ''
        end if
    end subroutine report_stop

    !> Before any run: --out names a folder (created with its parents when missing, except
    !> for --check, which writes nothing), no two decks write the same result files, and
    !> no run writes over a deck (a deck named dam.out, dam.h5, ...).
    subroutine check_outputs(options, decks, error)
        type(options_t), intent(in) :: options
        character(len=*), intent(in) :: decks(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=len(decks)), allocatable :: named(:)
        named = pack(decks, len_trim(decks) > 0)   ! cfrd --restart without a deck: none
        if (allocated(options%out_dir)) then
            if (path_exists(options%out_dir) .and. .not. is_directory(options%out_dir)) then
                call fatal_error(error, '--out '//options%out_dir//': a file of that name '// &
                                 'exists; --out names the folder for the results', usage_error)
                return
            end if
            call check_result_names(named, error, options%out_dir)
            if (.not. allocated(error) .and. .not. options%check_only) &
                call check_inputs_kept(named, error, options%out_dir)
            if (.not. allocated(error) .and. .not. options%check_only) &
                call make_directories(options%out_dir, error)
        else
            call check_result_names(named, error)
            if (.not. allocated(error) .and. .not. options%check_only) &
                call check_inputs_kept(named, error)
        end if
    end subroutine check_outputs

    !> After each stage: write it to the result files behind the analysis of the next stage
    !> (cfrd_stage_writer), then print its progress line (report_stage). After a failed
    !> write nothing more is written and the stages are still reported; run_deck takes the
    !> error when the analysis returns.
    subroutine stream_stage(number, total, stage)
        integer, intent(in) :: number, total
        type(stage_result_t), intent(in) :: stage
        if (copies_stage(number)) then
            ! cfrd --restart: a stored stage, stored as this run stores it: copied
            call write_stage_behind(current%output, current%model, number, total, stage, &
                                    report_stage, current%source%file_id)
        else
            call write_stage_behind(current%output, current%model, number, total, stage, &
                                    report_stage)
        end if
    end subroutine stream_stage

    !> A stage's progress line, once it is in the files (on the stage writer's thread).
    subroutine report_stage(number, total, stage)
        integer, intent(in) :: number, total
        type(stage_result_t), intent(in) :: stage
        ! Increments accepted above ERRTOL (error control at its depth limit): even --quiet.
        if (allocated(stage%warning)) write (error_unit, '(a,i0,a)') 'cfrd: warning: ', &
            stage%unbalanced, ' increment(s) accepted out of balance, the first: '// &
            stage%warning
        if (options%quiet) return
        write (output_unit, '(a,i0,a,i0,2a,i0,a,i0,a,i0,a,i0,a,es9.2,a,f8.3,a)') '  stage ', &
            number, '/', total, ': ', stage%name//', ', stage%increments, ' increments, ', &
            stage%factorisations, ' factorisations, ', stage%iterations, ' iterations, ', &
            stage%cutbacks, ' cutbacks, residual', stage%max_residual, ',', stage%wall_time, &
            ' s'
        flush (output_unit)
    end subroutine report_stage

    !> cfrd --restart: whether stage `number` is a stored one stored as this run stores
    !> its values (then its HDF5 group is copied).
    logical function copies_stage(number)
        integer, intent(in) :: number
        copies_stage = number <= current%source%from_stage .and. &
                       current%source%deflate == options%format%deflate .and. &
                       (current%source%single .eqv. options%format%single) .and. &
                       (current%source%full .eqv. options%format%full)
    end function copies_stage

    !> cfrd --restart: stage `number` as the results file continued from stored it.
    !> `light` stays true for a stage whose HDF5 group is copied (copies_stage) when no
    !> legacy listing needs its full results.
    subroutine stored_stage(number, stage, light, error)
        integer, intent(in) :: number
        type(stage_result_t), intent(out) :: stage
        logical, intent(inout) :: light
        type(error_t), allocatable, intent(out) :: error
        light = light .and. copies_stage(number) .and. .not. options%legacy_listing
        call read_restart_stage(current%source, number, stage, light, error)
    end subroutine stored_stage

    subroutine parse_command_line(options, decks, error)
        type(options_t), intent(out) :: options
        character(len=:), allocatable, intent(out) :: decks(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=4096) :: arg
        logical, allocatable :: is_results(:)
        integer :: i, n, ndeck, length
        n = command_argument_count()
        allocate (character(len=4096) :: decks(n))
        ndeck = 0
        i = 0
        do while (i < n)
            i = i + 1
            call get_command_argument(i, arg, length)
            if (length > len(arg)) then
                call fatal_error(error, 'argument '//to_text(i)//' is longer than '// &
                                 to_text(len(arg))//' characters', usage_error)
                return
            end if
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
            case ('--float32')
                options%format%single = .true.
            case ('--results')
                call next_word(i, n, arg)
                if (trim(arg) /= 'lean' .and. trim(arg) /= 'full') then
                    call fatal_error(error, 'option --results needs lean or full', usage_error)
                    return
                end if
                options%format%full = trim(arg) == 'full'
            case ('--compress')
                call next_number(i, n, 0, 9, options%format%deflate, error, &
                                 'option --compress needs a level from 0 (none) to 9')
                if (allocated(error)) return
            case ('--threads')
                call next_number(i, n, 1, 1024, options%threads, error, &
                                 'option --threads needs a number of threads from 1 to 1024')
                if (allocated(error)) return
            case ('--linear-solver')
                call next_word(i, n, arg)
                select case (trim(arg))
                case ('auto')
                    options%linear_solver = linear_solver_auto
                case ('cholmod')
                    options%linear_solver = linear_solver_cholmod
                case ('umfpack')
                    options%linear_solver = linear_solver_umfpack
                case default
                    call fatal_error(error, 'option --linear-solver needs auto, cholmod or '// &
                                     'umfpack', usage_error)
                    return
                end select
            case ('--restart', '--from-stage')
                if (i == n) then
                    call fatal_error(error, 'option '//trim(arg)//' needs a value', &
                                     usage_error)
                    return
                end if
                block
                    character(len=4096) :: value
                    integer :: stat
                    call get_command_argument(i + 1, value, length)
                    if (trim(arg) == '--restart') then
                        options%restart = trim(value)
                    else
                        read (value, *, iostat=stat) options%from_stage
                        if (stat /= 0 .or. options%from_stage < 1 .or. &
                            verify(trim(value), '0123456789') /= 0) then
                            call fatal_error(error, 'option --from-stage needs a stage '// &
                                             'number (1, 2, ...), not '''//trim(value)// &
                                             '''', usage_error)
                            return
                        end if
                    end if
                end block
                i = i + 1
            case ('-o', '--out')
                if (i == n) then
                    call fatal_error(error, 'option '//trim(arg)//' needs a directory', &
                                     usage_error)
                    return
                end if
                i = i + 1
                call get_command_argument(i, arg, length)
                if (len_trim(arg) == 0 .or. length > len(arg)) then
                    call fatal_error(error, 'option --out needs a folder name of 1 to '// &
                                     to_text(len(arg))//' characters', usage_error)
                    return
                end if
                options%out_dir = trim(arg)
            case default
                if (arg(1:1) == '-') then
                    call fatal_error(error, "unknown option '"//trim(arg)//"'", usage_error)
                    return
                end if
                ndeck = ndeck + 1
                decks(ndeck) = arg
            end select
        end do
        ! With --check, a folder or a results file names result sets to check, not a deck.
        allocate (is_results(ndeck))
        is_results = .false.
        if (options%check_only) then
            do i = 1, ndeck
                is_results(i) = is_results_path(trim(decks(i)))
            end do
        end if
        allocate (character(len=4096) :: options%result_paths(count(is_results)))
        n = 0
        ndeck = 0
        do i = 1, size(is_results)
            if (is_results(i)) then
                n = n + 1
                options%result_paths(n) = decks(i)
            else
                ndeck = ndeck + 1
                decks(ndeck) = decks(i)
            end if
        end do
        decks = decks(1:ndeck)
        if (options%from_stage > 0 .and. .not. allocated(options%restart)) then
            call fatal_error(error, 'option --from-stage goes with --restart', usage_error)
            return
        end if
        if (allocated(options%restart)) then
            ! cfrd --restart RESULTS.h5 [--from-stage K] [DECK]: one deck at most; none
            ! continues the deck stored in RESULTS.h5 (its name '')
            if (size(decks) > 1 .or. options%check_only) then
                call fatal_error(error, 'option --restart takes at most one deck, and '// &
                                 'no --check', usage_error)
                return
            end if
            if (size(decks) == 0) decks = [character(len=4096) :: '']
            return
        end if
        if (size(decks) + size(options%result_paths) == 0) then
            call fatal_error(error, 'no deck given', usage_error)
            return
        end if
    end subroutine parse_command_line

    !> The option's value: argument i + 1 (i moves past it), digits only, from lowest to
    !> highest; otherwise a usage error with `message`.
    !> The argument after option i (i advanced to it); `arg` unchanged (the option) when
    !> the option is the last argument.
    subroutine next_word(i, n, arg)
        integer, intent(inout) :: i
        integer, intent(in) :: n
        character(len=*), intent(inout) :: arg
        integer :: length
        if (i < n) then
            i = i + 1
            call get_command_argument(i, arg, length)
        end if
    end subroutine next_word

    subroutine next_number(i, n, lowest, highest, value, error, message)
        integer, intent(inout) :: i
        integer, intent(in) :: n, lowest, highest
        integer, intent(inout) :: value
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: message
        character(len=32) :: arg
        integer :: length, stat, number
        number = lowest - 1
        if (i < n) then
            i = i + 1
            call get_command_argument(i, arg, length)
            read (arg, *, iostat=stat) number
            if (stat /= 0 .or. length > len(arg) .or. length == 0 .or. &
                verify(arg(1:min(length, len(arg))), '0123456789') /= 0) number = lowest - 1
        end if
        if (number < lowest .or. number > highest) then
            call fatal_error(error, message, usage_error)
            return
        end if
        value = number
    end subroutine next_number

    !> cfrd --check DIR / RESULTS.h5: whether each result set is whole (docs/results.md,
    !> "Result sets"); `worst` becomes 1 when one is not, 2 for a path that names none.
    subroutine check_result_sets(paths, worst)
        character(len=*), intent(in) :: paths(:)
        integer, intent(inout) :: worst
        type(error_t), allocatable :: error
        logical :: whole
        integer :: k
        do k = 1, size(paths)
            call check_results(trim(paths(k)), output_unit, whole, error)
            if (allocated(error)) then
                write (error_unit, '(a)') 'cfrd: '//error%message
                worst = max(worst, error_status(error))
            else if (.not. whole) then
                worst = max(worst, 1)
            end if
        end do
    end subroutine check_result_sets

    subroutine print_help()
        write (output_unit, '(a)') &
            'Usage: cfrd [options] DECK [DECK ...]', &
            '       cfrd --check DIR|RESULTS.h5 [...]', &
            '       cfrd [options] --restart RESULTS.h5 [--from-stage K] [DECK]', &
            '', &
            'Runs each card deck (docs/cards.md) and writes DECK.out (listing), DECK.h5', &
            '(results, docs/results.md) and DECK.xmf (for ParaView) beside it, or in', &
            '--out DIR. A failed analysis keeps its completed stages in', &
            'DECK.incomplete.h5 and leaves earlier results untouched; so does a run', &
            'stopped by SIGINT (Ctrl-C) or SIGTERM (Slurm''s time limit): it stops before', &
            'the next load increment. A second signal of the same kind ends it at once.', &
            'The files of a run are one result set: they carry one run id and replace the', &
            'earlier set all together at the end; DECK.lock keeps a second run of the same', &
            'set out (exit 2). A result name that is a deck (dam.out) is refused (exit 2).', &
            '', &
            'Options:', &
            '  --check       read and validate the decks only; given a folder or a', &
            '                results file (.h5), say whether each result set in it is', &
            '                whole (same run id, its deck unchanged): exit 0 when all', &
            '                are, 1 when one is not', &
            '  --restart RESULTS.h5', &
            '                continue from a stage of a results file (DECK.h5 or', &
            '                DECK.incomplete.h5): without DECK its stored deck, into its', &
            '                result set; with DECK that deck''s later stages, once it is', &
            '                found to be the stored deck up to that stage (exit 2 naming', &
            '                the first difference otherwise)', &
            '  --from-stage K  the stage to continue from (default: the last completed)', &
            '  --out DIR     write results into DIR (created if missing); two decks of', &
            '                the same name are refused (exit 2)', &
            '  --quiet       print nothing but errors', &
            '  --compress N  deflate level of the HDF5 datasets, 0 (none) to 9; default 1', &
            '                (with the shuffle filter; lossless, about half the size)', &
            '  --float32     store the stages'' fields in single precision (7 digits):', &
            '                half the size again; the mesh and attributes stay double', &
            '  --results lean|full', &
            '                lean (default): what is derived from other datasets', &
            '                (stress_centroid, principal) or stored twice (the', &
            '                z-padded displacement copies) is not written, and what', &
            '                repeats is linked (tools/cfrdtools recomputes the rest bit', &
            '                for bit); full: also those, as before (docs/results.md)', &
            '  --threads N   OpenMP threads of the element loops (assembly, stress', &
            '                update); default OMP_NUM_THREADS, else 1. The results are', &
            '                the same bits for any N; the factorisation stays on one', &
            '                thread (CFRD_BLAS_THREADS); with N > 1 set', &
            '                OMP_WAIT_POLICY=passive on a shared machine', &
            '  --legacy-listing', &
            '                also write DECK.lst: the legacy codes'' per-layer tables of', &
            '                node displacements and element stresses and stress levels', &
            '  --linear-solver auto|cholmod|umfpack', &
            '                the sparse solver: auto (default) CHOLMOD for the symmetric', &
            '                positive definite matrices (with contact: for K, through its', &
            '                Schur complement on the contact nodes), UMFPACK for the rest', &
            '                and for those CHOLMOD declines; cholmod: an error where it', &
            '                declines a symmetric one; umfpack: UMFPACK for all', &
            '  --version     print the version', &
            '  --help        print this help', &
            '', &
            'Exit status: 0 all decks ran, 1 a numerical or file failure, 2 bad input or', &
            'usage, 130 stopped by SIGINT, 143 stopped by SIGTERM (the remaining decks', &
            'are not run).'
    end subroutine print_help
end program cfrd_main
