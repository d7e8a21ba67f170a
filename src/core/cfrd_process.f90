!> The running process as a lock on a result set needs it (io/cfrd_result_lock.f90): its
!> id, the host it runs on, its start in clock ticks since boot (so that a lock left by a
!> process whose id was since reused is known for stale), whether a process of this host
!> still runs, random bits for run ids, and a short sleep. Linux only (/proc), bound to the
!> C library in two layers.
module cfrd_process
    use, intrinsic :: iso_c_binding, only: c_int, c_char, c_size_t, c_ptrdiff_t, c_null_char
    use, intrinsic :: iso_fortran_env, only: int64
    implicit none
    private

    public :: process_id, host_name, process_start_ticks, process_running, can_see_processes
    public :: random_hex, sleep_milliseconds

    interface
        integer(c_int) function c_getpid() bind(C, name='getpid')
            import :: c_int
        end function c_getpid

        integer(c_int) function c_gethostname(name, length) bind(C, name='gethostname')
            import :: c_int, c_char, c_size_t
            character(kind=c_char), intent(out) :: name(*)
            integer(c_size_t), value :: length
        end function c_gethostname

        integer(c_int) function c_usleep(microseconds) bind(C, name='usleep')
            import :: c_int
            integer(c_int), value :: microseconds   ! useconds_t: unsigned int
        end function c_usleep

        !> getrandom(2) (glibc 2.25, Linux 3.17): up to `length` random bytes, the count
        !> returned (-1 on error); ssize_t is c_ptrdiff_t's size on Linux (LP64 and ILP32).
        integer(c_ptrdiff_t) function c_getrandom(buffer, length, flags) bind(C, name='getrandom')
            import :: c_ptrdiff_t, c_size_t, c_int, c_char
            character(kind=c_char), intent(out) :: buffer(*)
            integer(c_size_t), value :: length
            integer(c_int), value :: flags
        end function c_getrandom

        integer(c_int) function c_access(path, mode) bind(C, name='access')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: mode
        end function c_access
    end interface

contains

    !> This process's id.
    integer function process_id()
        process_id = int(c_getpid())
    end function process_id

    !> The host's name (gethostname(2)); 'unknown' if it cannot be had.
    function host_name() result(name)
        character(len=:), allocatable :: name
        character(kind=c_char) :: buffer(256)
        integer :: n
        buffer = c_null_char
        if (c_gethostname(buffer, size(buffer, kind=c_size_t) - 1) /= 0) then
            name = 'unknown'
            return
        end if
        n = 0
        do while (n < size(buffer) - 1)
            if (buffer(n + 1) == c_null_char) exit
            n = n + 1
        end do
        allocate (character(len=n) :: name)
        name = transfer(buffer(1:n), name)
        if (n == 0) name = 'unknown'
    end function host_name

    !> Whether this system shows its processes in /proc (Linux): without it no process can
    !> be known to have ended.
    logical function can_see_processes()
        can_see_processes = c_access('/proc/self/stat'//c_null_char, 0_c_int) == 0
    end function can_see_processes

    !> The start time of process `pid` in clock ticks after boot (field 22 of
    !> /proc/PID/stat), as text; '' when the process does not exist or it cannot be read.
    function process_start_ticks(pid) result(ticks)
        integer, intent(in) :: pid
        character(len=:), allocatable :: ticks
        character(len=1024) :: line
        character(len=16) :: number
        integer :: unit, stat, close_paren, field, k, first
        ticks = ''
        write (number, '(i0)') pid
        open (newunit=unit, file='/proc/'//trim(number)//'/stat', action='read', &
              status='old', iostat=stat)
        if (stat /= 0) return
        line = ''
        read (unit, '(a)', iostat=stat) line
        close (unit)
        if (stat /= 0) return
        ! pid (comm) state ppid ...: the command may hold blanks and parentheses, so count
        ! fields from the last ')'; the state is field 3, the start time field 22.
        close_paren = index(line, ')', back=.true.)
        if (close_paren == 0) return
        field = 2
        k = close_paren + 1
        do while (k <= len_trim(line))
            if (line(k:k) == ' ') then
                k = k + 1
                cycle
            end if
            field = field + 1
            first = k
            do while (k <= len_trim(line))
                if (line(k:k) == ' ') exit
                k = k + 1
            end do
            if (field == 22) then
                ticks = line(first:k - 1)
                return
            end if
        end do
    end function process_start_ticks

    !> Whether process `pid` of this host still runs: /proc/PID exists and, when
    !> `start_ticks` is given (not ''), it started then (else the id was reused).
    logical function process_running(pid, start_ticks)
        integer, intent(in) :: pid
        character(len=*), intent(in) :: start_ticks
        character(len=:), allocatable :: now
        now = process_start_ticks(pid)
        if (len(now) == 0) then
            process_running = .false.
        else if (len_trim(start_ticks) == 0) then
            process_running = .true.
        else
            process_running = now == trim(start_ticks)
        end if
    end function process_running

    !> `n` random hex digits from the kernel's generator (getrandom(2), the source of
    !> /dev/urandom; the clock and the process id if it fails: unique enough to tell runs
    !> apart). getrandom takes the bytes asked for, where a Fortran stream read of
    !> /dev/urandom filled its whole buffer, 128 KiB, half a millisecond of a small deck's
    !> run (docs/performance.md (ae)).
    function random_hex(n) result(hex)
        integer, intent(in) :: n
        character(len=n) :: hex
        character(len=*), parameter :: digits = '0123456789abcdef'
        character(kind=c_char) :: bytes((n + 1)/2)
        integer :: k, value
        integer(int64) :: clock, mixed
        if (c_getrandom(bytes, int(size(bytes), c_size_t), 0_c_int) /= size(bytes)) then
            call system_clock(clock)
            mixed = ieor(clock, shiftl(int(process_id(), int64), 32))
            do k = 1, size(bytes)
                bytes(k) = char(int(iand(shiftr(mixed, 8*mod(k - 1, 8)), 255_int64)))
            end do
        end if
        do k = 1, n
            value = ichar(bytes((k + 1)/2))
            if (mod(k, 2) == 1) then
                value = value/16
            else
                value = mod(value, 16)
            end if
            hex(k:k) = digits(value + 1:value + 1)
        end do
    end function random_hex

    !> Wait `ms` milliseconds.
    subroutine sleep_milliseconds(ms)
        integer, intent(in) :: ms
        integer(c_int) :: status
        status = c_usleep(int(1000*ms, c_int))
    end subroutine sleep_milliseconds
end module cfrd_process
