!> `cfrd --check DIR` and `cfrd --check RESULTS.h5` (docs/results.md, "Result sets"): for
!> each result set (a DECK.h5 or DECK.incomplete.h5 and the files beside it), whether its
!> files carry the run id of its results file and are the files it lists (root attribute
!> `set_files`), whether the results file is complete, and whether the deck beside it (or
!> at the recorded `deck_path`) has the recorded SHA-256. It also names a lock (a run
!> writing the set, or a stale lock) and temporary files a killed run left. The set is whole
!> when nothing is missing, mixed or changed; files a cfrd run id does not mark are left
!> alone, except those of the set's names.
module cfrd_set_check
    use hdf5, only: hid_t, h5close_f, h5fopen_f, h5fclose_f, h5eset_auto_f, &
                    H5F_ACC_RDONLY_F
    use cfrd_h5_deflate, only: h5_open
    use cfrd_h5_read, only: text_attribute, int_attribute
    use cfrd_error, only: error_t, fatal_error, usage_error
    use cfrd_strings, only: to_text
    use cfrd_sha256, only: file_sha256
    use cfrd_files, only: path_exists, is_directory, folder_files, folder_name, base_name
    use cfrd_run_identity, only: text_run_id
    use cfrd_result_lock, only: lock_holder_t, read_lock, lock_is_stale, holder_text
    use cfrd_run_output, only: set_endings, lock_ending, incomplete_ending
    implicit none
    private

    public :: check_results, is_results_path

    !> What a results file says of its set.
    type :: set_record_t
        logical :: readable = .false.
        character(len=:), allocatable :: run_id, deck_sha256, deck_file, deck_path
        character(len=:), allocatable :: set_files, failure
        integer :: complete = -1, stages_completed = -1, stages_total = -1
        integer :: layout_version = -1
    end type set_record_t

contains

    !> Whether a --check argument names results (a folder, or a file ending in .h5) rather
    !> than a deck.
    logical function is_results_path(path)
        character(len=*), intent(in) :: path
        integer :: n
        n = len_trim(path)
        is_results_path = is_directory(trim(path))
        if (n > 3) is_results_path = is_results_path .or. path(n - 2:n) == '.h5'
    end function is_results_path

    !> Check the result sets of the folder `path`, or the one of the results file `path`,
    !> writing a line per set to `unit`. `whole` is false when a set is not whole; an error
    !> (usage) when `path` is neither, or the folder holds no result set.
    subroutine check_results(path, unit, whole, error)
        character(len=*), intent(in) :: path
        integer, intent(in) :: unit
        logical, intent(out) :: whole
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: names(:), folder, name
        logical :: set_whole
        integer :: k, nsets, nwhole, hdferr
        whole = .true.
        if (is_directory(path)) then
            folder = path
            call folder_files(folder, names)
        else if (path_exists(path) .and. index(base_name(path), '.h5', back=.true.) == &
                 len(base_name(path)) - 2) then
            folder = folder_name(path)
            names = [character(len=len(base_name(path))) :: base_name(path)]
        else
            call fatal_error(error, '--check '//path//': no such folder or results file '// &
                             '(.h5)', usage_error)
            return
        end if
        call h5_open(hdferr)
        call h5eset_auto_f(0, hdferr)    ! our messages, not HDF5's error stack on stderr
        nsets = 0
        nwhole = 0
        do k = 1, size(names)
            name = trim(names(k))
            if (len(name) <= 3) cycle
            if (name(len(name) - 2:) /= '.h5') cycle
            nsets = nsets + 1
            call check_set(folder, name(:len(name) - 3), unit, set_whole)
            if (set_whole) nwhole = nwhole + 1
            whole = whole .and. set_whole
        end do
        ! Files of a set whose results file is gone, and runs writing a first set.
        if (is_directory(path)) then
            do k = 1, size(names)
                call check_orphan(folder, trim(names(k)), names, unit, set_whole)
                if (.not. set_whole) nsets = nsets + 1
                whole = whole .and. set_whole
            end do
        end if
        call h5close_f(hdferr)
        if (nsets == 0) then
            call fatal_error(error, '--check '//path//': no result set (DECK.h5) in it', &
                             usage_error)
            return
        end if
        if (is_directory(path)) write (unit, '(a)') path//': '//to_text(nsets)// &
            ' result sets, '//to_text(nwhole)//' whole, '//to_text(nsets - nwhole)//' not'
    end subroutine check_results

    !> One set: the results file STEM.h5 in `folder` and the files beside it.
    subroutine check_set(folder, stem, unit, whole)
        character(len=*), intent(in) :: folder, stem
        integer, intent(in) :: unit
        logical, intent(out) :: whole
        type(set_record_t) :: record
        character(len=:), allocatable :: at, h5_name, problems, notes, listed, file, other
        character(len=:), allocatable :: verdict
        logical :: is_incomplete
        integer :: k
        at = folder//'/'
        if (folder(len(folder):) == '/') at = folder
        h5_name = stem//'.h5'
        problems = ''
        notes = ''
        call read_record(at//h5_name, record)
        is_incomplete = index(stem, incomplete_ending, back=.true.) > 0 .and. &
                        index(stem, incomplete_ending, back=.true.) == &
                        len(stem) - len(incomplete_ending) + 1
        if (.not. record%readable) then
            call add(problems, h5_name//' cannot be read as a cfrd results file')
            verdict = 'UNREADABLE'
        else if (len(record%run_id) == 0) then
            call add(problems, h5_name//' has no run id (results layout '// &
                     to_text(record%layout_version)//', before 3): cannot tell')
            verdict = 'CANNOT TELL'
        else
            ! The files the results file lists: each there, and of its run.
            listed = new_line('a')//record%set_files//new_line('a')
            do k = 1, count_lines(record%set_files)
                file = line_of(record%set_files, k)
                if (file == h5_name) cycle
                if (.not. path_exists(at//file)) then
                    call add(problems, file//' missing')
                else
                    other = text_run_id(at//file)
                    if (other /= record%run_id) call add(problems, file//' is of '// &
                                                         run_text(other)//', '//h5_name// &
                                                         ' of run '//record%run_id)
                end if
            end do
            ! The set's other names: a file there is of another run.
            do k = 1, size(set_endings)
                file = stem//trim(set_endings(k))
                if (file == h5_name .or. index(listed, new_line('a')//file//new_line('a')) > 0) &
                    cycle
                if (path_exists(at//file)) call add(problems, file//' is of '// &
                                                    run_text(text_run_id(at//file))// &
                                                    ', not listed in '//h5_name)
            end do
            if (len(problems) > 0) verdict = 'MIXED'
            if (is_incomplete) then
                call add(notes, 'incomplete: '//to_text(record%stages_completed)//' of '// &
                         to_text(record%stages_total)//' stages')
            else if (record%complete /= 1) then
                call add(problems, h5_name//' is not complete (complete = '// &
                         to_text(record%complete)//')')
                if (.not. allocated(verdict)) verdict = 'NOT COMPLETE'
            end if
            call check_deck(at, record, problems, notes, verdict)
        end if
        call check_lock_and_parts(at, stem, notes)
        whole = len(problems) == 0
        if (whole) then
            verdict = 'whole'
            problems = 'run '//record%run_id//', '//to_text(count_lines(record%set_files))// &
                       ' files'
        else if (.not. allocated(verdict)) then
            verdict = 'NOT WHOLE'
        end if
        if (len(notes) > 0) problems = problems//'; '
        write (unit, '(a)') at//stem//': '//verdict//': '//problems//notes
    end subroutine check_set

    !> The deck of a set: beside it (the recorded deck's name in the set's folder), else at
    !> the recorded absolute path; its SHA-256 against the recorded one.
    subroutine check_deck(at, record, problems, notes, verdict)
        character(len=*), intent(in) :: at
        type(set_record_t), intent(in) :: record
        character(len=:), allocatable, intent(inout) :: problems, notes, verdict
        character(len=:), allocatable :: deck
        character(len=64) :: digest
        type(error_t), allocatable :: error
        deck = ''
        if (len(record%deck_file) > 0) then
            if (path_exists(at//base_name(record%deck_file))) &
                deck = at//base_name(record%deck_file)
        end if
        if (len(deck) == 0 .and. len(record%deck_path) > 0) then
            if (path_exists(record%deck_path)) deck = record%deck_path
        end if
        if (len(deck) == 0) then
            call add(notes, 'deck not found (it was '//record%deck_file//')')
            return
        end if
        call file_sha256(deck, digest, error)
        if (allocated(error)) then
            call add(problems, 'the deck '//deck//' cannot be read')
        else if (digest /= record%deck_sha256) then
            call add(problems, 'the deck '//deck//' has changed since the run (SHA-256 '// &
                     digest(1:12)//'..., the run''s '//record%deck_sha256(1:min(12, &
                     len(record%deck_sha256)))//'...)')
            if (.not. allocated(verdict)) verdict = 'DECK CHANGED'
        else
            call add(notes, 'deck '//deck//' has the recorded SHA-256')
        end if
    end subroutine check_deck

    !> A lock on the set (a run writing it, or stale) and temporary files left by a kill.
    subroutine check_lock_and_parts(at, stem, notes)
        character(len=*), intent(in) :: at, stem
        character(len=:), allocatable, intent(inout) :: notes
        type(lock_holder_t) :: holder
        logical :: writing
        integer :: k
        writing = .false.
        if (path_exists(at//stem//lock_ending)) then
            call read_lock(at//stem//lock_ending, holder)
            if (lock_is_stale(holder)) then
                call add(notes, 'stale lock '//stem//lock_ending//' of '//holder_text(holder)// &
                         ' (the next run takes it over)')
            else if (holder%readable) then
                writing = .true.
                call add(notes, 'being written by '//holder_text(holder))
            else
                call add(notes, 'a lock '//stem//lock_ending//' that cfrd cannot read')
            end if
        end if
        if (writing) return
        do k = 1, size(set_endings)
            if (path_exists(at//stem//trim(set_endings(k))//'.part')) &
                call add(notes, stem//trim(set_endings(k))//'.part left by a run that was '// &
                         'killed')
            if (path_exists(at//stem//trim(set_endings(k))//'.prev')) &
                call add(notes, stem//trim(set_endings(k))//'.prev left by a run killed '// &
                         'while it renamed its files')
        end do
    end subroutine check_lock_and_parts

    !> A file of a set's names (with a cfrd run id) whose results file is missing: that set
    !> is not whole. A lock without a results file: a run writing its first set.
    subroutine check_orphan(folder, name, names, unit, whole)
        character(len=*), intent(in) :: folder, name
        character(len=*), intent(in) :: names(:)
        integer, intent(in) :: unit
        logical, intent(out) :: whole
        character(len=:), allocatable :: at, stem, run_id, notes
        integer :: k, n
        whole = .true.
        at = folder//'/'
        if (folder(len(folder):) == '/') at = folder
        do k = 1, size(set_endings)
            if (trim(set_endings(k)) == '.h5') cycle
            n = len(name) - len_trim(set_endings(k))
            if (n < 1) cycle
            if (name(n + 1:) /= trim(set_endings(k))) cycle
            stem = name(:n)
            if (any(names == stem//'.h5')) return
            run_id = text_run_id(at//name)
            if (len(run_id) == 0) return          ! not a file of cfrd's (or before layout 3)
            whole = .false.
            write (unit, '(a)') at//stem//': MIXED: '//name//' of run '//run_id//' without '// &
                stem//'.h5'
            return
        end do
        n = len(name) - len(lock_ending)
        if (n < 1) return
        if (name(n + 1:) /= lock_ending) return
        stem = name(:n)
        if (any(names == stem//'.h5')) return
        notes = ''
        call check_lock_and_parts(at, stem, notes)
        write (unit, '(a)') at//stem//': no results yet: '//notes
    end subroutine check_orphan

    !> The root attributes of a results file (readable = .false. when it cannot be opened).
    subroutine read_record(path, record)
        character(len=*), intent(in) :: path
        type(set_record_t), intent(out) :: record
        integer(hid_t) :: file_id
        integer :: hdferr
        character(len=:), allocatable :: program
        record%run_id = ''
        record%deck_sha256 = ''
        record%deck_file = ''
        record%deck_path = ''
        record%set_files = ''
        record%failure = ''
        call h5fopen_f(path, H5F_ACC_RDONLY_F, file_id, hdferr)
        if (hdferr < 0) return
        program = text_attribute(file_id, 'program')
        if (program == 'cfrd') then
            record%readable = .true.
            record%run_id = text_attribute(file_id, 'run_id')
            record%deck_sha256 = text_attribute(file_id, 'deck_sha256')
            record%deck_file = text_attribute(file_id, 'deck_file')
            record%deck_path = text_attribute(file_id, 'deck_path')
            record%set_files = text_attribute(file_id, 'set_files')
            record%complete = int_attribute(file_id, 'complete')
            record%stages_completed = int_attribute(file_id, 'stages_completed')
            record%stages_total = int_attribute(file_id, 'stages_total')
            record%layout_version = int_attribute(file_id, 'layout_version')
        end if
        call h5fclose_f(file_id, hdferr)
    end subroutine read_record

    !> 'run ID', or 'no run id' for a file that has none.
    function run_text(run_id) result(text)
        character(len=*), intent(in) :: run_id
        character(len=:), allocatable :: text
        if (len(run_id) == 0) then
            text = 'no run'
        else
            text = 'run '//run_id
        end if
    end function run_text

    !> Append `item` to a '; '-separated list.
    subroutine add(list, item)
        character(len=:), allocatable, intent(inout) :: list
        character(len=*), intent(in) :: item
        if (len(list) > 0) list = list//'; '
        list = list//item
    end subroutine add

    !> The number of LF-separated lines of `text` (0 when empty).
    pure integer function count_lines(text)
        character(len=*), intent(in) :: text
        integer :: k
        count_lines = 0
        if (len(text) == 0) return
        count_lines = 1
        do k = 1, len(text)
            if (text(k:k) == new_line('a')) count_lines = count_lines + 1
        end do
    end function count_lines

    !> Line `n` of LF-separated `text`.
    pure function line_of(text, n) result(line)
        character(len=*), intent(in) :: text
        integer, intent(in) :: n
        character(len=:), allocatable :: line
        integer :: first, k, found
        first = 1
        found = 1
        do k = 1, len(text)
            if (text(k:k) /= new_line('a')) cycle
            if (found == n) exit
            found = found + 1
            first = k + 1
        end do
        line = text(first:k - 1)
    end function line_of
end module cfrd_set_check
