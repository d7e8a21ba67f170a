!> The command line: parses options, and for each deck calls the reader, the analysis and the
!> writers. The only place where an error_t becomes an exit status.
program cfrd_main
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
    use cfrd_error, only: error_t, fatal_error, error_status, usage_error
    use cfrd_version, only: cfrd_version_string
    use cfrd_model, only: model_t
    use cfrd_results, only: results_t
    use cfrd_deck, only: read_deck
    use cfrd_stage_driver, only: run_analysis
    use cfrd_results, only: stage_result_t
    use cfrd_listing, only: write_listing, write_summary, write_gauge_csv
    use cfrd_legacy_listing, only: write_legacy_listing
    use cfrd_hdf5, only: write_results_h5
    use cfrd_interface_io, only: write_interface_csv, has_interfaces, has_slab
    use cfrd_files, only: move_file, delete_file, base_name, strip_extension
    use cfrd_memory, only: tune_allocator
    implicit none

    type :: options_t
        logical :: check_only = .false.
        logical :: quiet = .false.
        logical :: legacy_listing = .false.   !! also DECK.lst, the legacy-style tables
        character(len=:), allocatable :: out_dir
    end type options_t

    type(options_t) :: options
    character(len=:), allocatable :: decks(:)
    type(error_t), allocatable :: error
    integer :: i, status, worst

    call tune_allocator()
    call parse_command_line(options, decks, error)
    if (allocated(error)) then
        write (error_unit, '(a)') 'cfrd: '//error%message
        write (error_unit, '(a)') "Try 'cfrd --help'."
        call exit(error_status(error))
    end if

    worst = 0
    do i = 1, size(decks)
        call run_deck(trim(decks(i)), options, status)
        worst = max(worst, status)
    end do
    call exit(worst)

contains

    subroutine run_deck(path, options, status)
        character(len=*), intent(in) :: path
        type(options_t), intent(in) :: options
        integer, intent(out) :: status
        type(model_t) :: model
        type(results_t) :: results
        type(error_t), allocatable :: error
        character(len=:), allocatable :: stem
        integer :: i

        status = 0
        call read_deck(path, model, error)
        if (.not. allocated(error)) then
            do i = 1, size(model%warnings)
                write (error_unit, '(a)') 'cfrd: warning: '//path//': '//trim(model%warnings(i))
            end do
        end if
        if (.not. allocated(error) .and. options%check_only) then
            if (.not. options%quiet) write (output_unit, '(a,i0,a,i0,a)') path//': OK (', &
                model%mesh%nnode, ' nodes, ', model%mesh%nelem, ' elements)'
            return
        end if
        if (.not. allocated(error)) then
            if (options%quiet) then
                call run_analysis(model, results, error)
            else
                call run_analysis(model, results, error, print_progress)
            end if
        end if
        if (.not. allocated(error)) then
            if (allocated(options%out_dir)) then
                stem = options%out_dir//'/'//strip_extension(base_name(path))
            else
                stem = strip_extension(path)
            end if
            call write_results(stem, model, results, options%legacy_listing, error)
        end if
        if (allocated(error)) then
            write (error_unit, '(a)') 'cfrd: '//error%message
            status = error_status(error)
            return
        end if
        if (.not. options%quiet) then
            call write_summary(output_unit, model, results)
            if (size(model%gauges) > 0) then
                write (output_unit, '(a)') 'Results: '//stem//'.out, '//stem//'.h5, '// &
                    stem//'-gauges.csv'
            else
                write (output_unit, '(a)') 'Results: '//stem//'.out, '//stem//'.h5'
            end if
            if (options%legacy_listing) write (output_unit, '(a)') &
                'Legacy-style listing: '//stem//'.lst'

        end if
    end subroutine run_deck

    !> One line per stage on the terminal.
    subroutine print_progress(number, total, stage)
        integer, intent(in) :: number, total
        type(stage_result_t), intent(in) :: stage
        write (output_unit, '(a,i0,a,i0,2a,i0,a,i0,a,i0,a,i0,a,es9.2,a,f8.3,a)') '  stage ', &
            number, '/', total, ': ', stage%name//', ', stage%increments, ' increments, ', &
            stage%factorisations, ' factorisations, ', stage%iterations, ' iterations, ', &
            stage%cutbacks, ' cutbacks, residual', stage%max_residual, ',', stage%wall_time, &
            ' s'
        flush (output_unit)
    end subroutine print_progress

    !> Write the result files under temporary names, then rename them into place, so that a
    !> failed run leaves the results of an earlier run untouched.
    subroutine write_results(stem, model, results, legacy_listing, error)
        character(len=*), intent(in) :: stem
        type(model_t), intent(in) :: model
        type(results_t), intent(in) :: results
        logical, intent(in) :: legacy_listing
        type(error_t), allocatable, intent(out) :: error
        character(len=*), parameter :: part = '.part'
        ! The files beside the listing and the HDF5 file, each written when its flag is set.
        character(len=*), parameter :: others(5) = [character(len=14) :: '-gauges.csv', &
                                                 '-interface.csv', '-openings.csv', '-slab.csv', &
                                                 '.lst']
        logical :: written(5)
        integer :: k
        written = [size(model%gauges) > 0, has_interfaces(model), has_interfaces(model), &
                   has_slab(model), legacy_listing]
        call write_listing(stem//'.out'//part, model, results, error)
        if (.not. allocated(error)) call write_results_h5(stem//'.h5'//part, model, results, &
                                                          error)
        if (.not. allocated(error) .and. written(1)) &
            call write_gauge_csv(stem//'-gauges.csv'//part, model, results, error)
        if (.not. allocated(error)) call write_interface_csv(stem, part, model, results, error)
        if (.not. allocated(error) .and. legacy_listing) &
            call write_legacy_listing(stem//'.lst'//part, model, results, error)
        if (.not. allocated(error)) call move_file(stem//'.out'//part, stem//'.out', error)
        if (.not. allocated(error)) call move_file(stem//'.h5'//part, stem//'.h5', error)
        do k = 1, size(others)
            if (.not. allocated(error) .and. written(k)) &
                call move_file(stem//trim(others(k))//part, stem//trim(others(k)), error)
        end do
        if (allocated(error)) then
            call delete_file(stem//'.out'//part)
            call delete_file(stem//'.h5'//part)
            do k = 1, size(others)
                call delete_file(stem//trim(others(k))//part)
            end do
        end if
    end subroutine write_results

    subroutine parse_command_line(options, decks, error)
        type(options_t), intent(out) :: options
        character(len=:), allocatable, intent(out) :: decks(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=4096) :: arg
        integer :: i, n, ndeck
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

    subroutine print_help()
        write (output_unit, '(a)') &
            'Usage: cfrd [options] DECK [DECK ...]', &
            '', &
            'Runs each card deck (docs/cards.md) and writes DECK.out (listing) and DECK.h5', &
            '(results, docs/results.md) beside it, or in --out DIR.', &
            '', &
            'Options:', &
            '  --check       read and validate the decks only', &
            '  --out DIR     write results into DIR (it must exist)', &
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
