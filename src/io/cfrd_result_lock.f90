!> The lock a run holds on its result set (docs/results.md, "Result sets"): DECK.lock in the
!> results folder, created exclusively (open with status='new', O_EXCL: of two runs that
!> try at once, one succeeds), holding the run id, the process id, host and start time. A
!> second run of the same set finds it and is refused, naming the first. A lock whose
!> process no longer runs on this host (no /proc/PID, or a process of that id that started
!> at another time) is stale: it is taken over with a warning. A lock of another host cannot
!> be checked and is never taken over. The lock is removed when its run ends, however it
!> ends short of a kill (then the next run takes it over).
module cfrd_result_lock
    use cfrd_error, only: error_t, fatal_error, usage_error, io_error
    use cfrd_strings, only: to_text
    use cfrd_files, only: path_exists, delete_file, move_file, link_file
    use cfrd_process, only: host_name, can_see_processes, process_running, sleep_milliseconds
    use cfrd_run_identity, only: run_identity_t
    implicit none
    private

    public :: result_lock_t, lock_holder_t, acquire_lock, release_lock, read_lock
    public :: holder_text, lock_is_stale

    !> The first line of a lock file.
    character(len=*), parameter :: lock_marker = 'cfrd result-set lock'

    !> A lock held by this run (`path` allocated while held).
    type :: result_lock_t
        character(len=:), allocatable :: path
        character(len=:), allocatable :: run_id
    end type result_lock_t

    !> What a lock file says of the run that holds it.
    type :: lock_holder_t
        logical :: readable = .false.       !! the marker, a run id, a pid and a host
        integer :: pid = 0
        character(len=:), allocatable :: run_id, host, started, start_ticks, deck
    end type lock_holder_t

contains

    !> Take the lock `path` for the run `identity`. Refused (usage error, exit 2) while
    !> another run holds it; a stale lock is taken over, and `warning` says so.
    subroutine acquire_lock(lock, path, identity, error, warning)
        type(result_lock_t), intent(out) :: lock
        character(len=*), intent(in) :: path
        type(run_identity_t), intent(in) :: identity
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable, intent(out) :: warning
        type(lock_holder_t) :: holder, moved
        type(error_t), allocatable :: move_error
        character(len=:), allocatable :: aside
        logical :: created
        integer :: attempt, wait
        do attempt = 1, 3
            call create_lock_file(path, identity, created, error)
            if (allocated(error)) return
            if (created) then
                lock%path = path
                lock%run_id = identity%run_id
                return
            end if
            ! A run that has just created the file may not have written it yet.
            call read_lock(path, holder)
            do wait = 1, 20
                if (holder%readable .or. .not. path_exists(path)) exit
                call sleep_milliseconds(50)
                call read_lock(path, holder)
            end do
            if (.not. path_exists(path)) cycle          ! released meanwhile
            if (.not. lock_is_stale(holder)) then
                call refuse(error, path, holder)
                return
            end if
            ! Stale. Move it aside before removing it, and remove it only if it is the one
            ! read: another run may have taken it over in between (then it goes back).
            aside = path//'.stale-'//to_text(identity%pid)
            call move_file(path, aside, move_error)
            if (allocated(move_error)) cycle            ! another run moved it first
            call read_lock(aside, moved)
            if (moved%run_id /= holder%run_id) then
                call link_file(aside, path, move_error)
                call delete_file(aside)
                call refuse(error, path, moved)
                return
            end if
            call delete_file(aside)
            warning = 'took over the stale lock '//path//' of '//holder_text(holder)// &
                      ': that process no longer runs'
        end do
        call read_lock(path, holder)
        call refuse(error, path, holder)
    end subroutine acquire_lock

    !> Remove the lock if it is still this run's (safe to call when none is held).
    subroutine release_lock(lock)
        type(result_lock_t), intent(inout) :: lock
        type(lock_holder_t) :: holder
        if (.not. allocated(lock%path)) return
        call read_lock(lock%path, holder)
        if (holder%readable) then
            if (holder%run_id == lock%run_id) call delete_file(lock%path)
        end if
        deallocate (lock%path)
    end subroutine release_lock

    !> What the lock file at `path` says (readable = .false. when it is missing, not a lock
    !> of cfrd, or not yet written whole).
    subroutine read_lock(path, holder)
        character(len=*), intent(in) :: path
        type(lock_holder_t), intent(out) :: holder
        character(len=4096) :: line
        integer :: unit, stat, blank
        holder%run_id = ''
        holder%host = ''
        holder%started = ''
        holder%start_ticks = ''
        holder%deck = ''
        open (newunit=unit, file=path, action='read', status='old', iostat=stat)
        if (stat /= 0) return
        read (unit, '(a)', iostat=stat) line
        if (stat /= 0 .or. trim(line) /= lock_marker) then
            close (unit)
            return
        end if
        do
            read (unit, '(a)', iostat=stat) line
            if (stat /= 0) exit
            blank = index(line, ' ')
            if (blank <= 1) cycle
            select case (line(:blank - 1))
            case ('run_id')
                holder%run_id = trim(line(blank + 1:))
            case ('pid')
                read (line(blank + 1:), *, iostat=stat) holder%pid
                if (stat /= 0) holder%pid = 0
            case ('host')
                holder%host = trim(line(blank + 1:))
            case ('started')
                holder%started = trim(line(blank + 1:))
            case ('start_ticks')
                holder%start_ticks = trim(line(blank + 1:))
            case ('deck')
                holder%deck = trim(line(blank + 1:))
            end select
        end do
        close (unit)
        holder%readable = len(holder%run_id) > 0 .and. holder%pid > 0 .and. &
                          len(holder%host) > 0
    end subroutine read_lock

    !> Whether the run that holds a lock is known to have ended: it ran on this host, and
    !> its process is gone (or the id now belongs to a process started at another time).
    logical function lock_is_stale(holder)
        type(lock_holder_t), intent(in) :: holder
        lock_is_stale = .false.
        if (.not. holder%readable) return
        if (holder%host /= host_name()) return
        if (.not. can_see_processes()) return
        lock_is_stale = .not. process_running(holder%pid, holder%start_ticks)
    end function lock_is_stale

    !> 'pid 123 on host node1, started 2026-11-25T08:23:02+01:00, run id ...'.
    function holder_text(holder) result(text)
        type(lock_holder_t), intent(in) :: holder
        character(len=:), allocatable :: text
        text = 'pid '//to_text(holder%pid)//' on host '//holder%host//', started '// &
               holder%started//', run id '//holder%run_id
    end function holder_text

    !> The error of a lock held by another run.
    subroutine refuse(error, path, holder)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: path
        type(lock_holder_t), intent(in) :: holder
        if (.not. holder%readable) then
            call fatal_error(error, 'the result set is locked by '//path//', which is not '// &
                             'a lock cfrd can read; remove it if no run writes these '// &
                             'results', usage_error)
        else if (holder%host /= host_name()) then
            call fatal_error(error, 'the result set is being written by another run: '// &
                             holder_text(holder)//' (lock '//path//'); it runs on another '// &
                             'host, so cfrd cannot tell whether it still runs: remove the '// &
                             'lock if it does not', usage_error)
        else
            call fatal_error(error, 'the result set is being written by another run: '// &
                             holder_text(holder)//' (lock '//path//'); wait for it to end, '// &
                             'or write elsewhere with --out DIR', usage_error)
        end if
    end subroutine refuse

    !> Create the lock file exclusively and write the run into it; `created` is false when
    !> it exists already; an error when it cannot be created for another reason.
    subroutine create_lock_file(path, identity, created, error)
        character(len=*), intent(in) :: path
        type(run_identity_t), intent(in) :: identity
        logical, intent(out) :: created
        type(error_t), allocatable, intent(out) :: error
        integer :: unit, stat
        character(len=256) :: msg
        created = .false.
        open (newunit=unit, file=path, status='new', action='write', iostat=stat, iomsg=msg)
        if (stat /= 0) then
            if (.not. path_exists(path)) call fatal_error(error, 'cannot create the lock '// &
                                                          path//': '//trim(msg), io_error)
            return
        end if
        write (unit, '(a)', iostat=stat, iomsg=msg) lock_marker, &
            'run_id '//identity%run_id, &
            'pid '//to_text(identity%pid), &
            'host '//identity%host, &
            'started '//identity%started, &
            'start_ticks '//identity%start_ticks, &
            'deck '//identity%deck_path
        if (stat == 0) close (unit, iostat=stat, iomsg=msg)
        if (stat /= 0) then
            close (unit, status='delete', iostat=stat)
            call fatal_error(error, 'cannot write the lock '//path//': '//trim(msg), io_error)
            return
        end if
        created = .true.
    end subroutine create_lock_file
end module cfrd_result_lock
