!> The identity of one run and of the result set it writes (docs/results.md, "Result
!> sets"): a run id that every file of the set carries (the listing's banner, the HDF5 root
!> attribute `run_id`, a comment in the XDMF file and in each CSV), the SHA-256 of the deck
!> as read, the deck's absolute path, and when and where the run started (the lock file
!> holds these too). text_run_id reads the run id back from a text file of a set.
module cfrd_run_identity
    use cfrd_error, only: error_t, fatal_error, input_error
    use cfrd_clock, only: iso_timestamp
    use cfrd_sha256, only: file_sha256
    use cfrd_process, only: process_id, host_name, process_start_ticks, random_hex
    use cfrd_files, only: resolved_path, path_exists
    implicit none
    private

    public :: run_identity_t, new_run_identity, text_run_id, run_id_width

    !> Characters of a run id: 'YYYYMMDDTHHMMSS-' and 16 random hex digits.
    integer, parameter :: run_id_width = 32
    !> The lines of a text file searched for its run id (it is in the first few).
    integer, parameter :: header_lines = 12

    !> Who made a result set, from which deck.
    type :: run_identity_t
        character(len=:), allocatable :: run_id        !! '20261125T082302-3f9a1c0b7d2e4a55'
        character(len=:), allocatable :: deck_sha256   !! 64 lowercase hex digits
        character(len=:), allocatable :: deck_path     !! absolute, links resolved
        character(len=:), allocatable :: started       !! ISO 8601 with the zone
        character(len=:), allocatable :: host
        integer :: pid = 0
        character(len=:), allocatable :: start_ticks   !! the process's start (/proc), or ''
    end type run_identity_t

contains

    !> A new run of the deck at `deck`: a fresh run id, the deck's SHA-256, this process.
    !> `known`: the deck's SHA-256 as a results file recorded it (a restart of the stored
    !> deck, cfrd --restart), not computed.
    subroutine new_run_identity(deck, identity, error, known)
        character(len=*), intent(in) :: deck
        type(run_identity_t), intent(out) :: identity
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: known
        character(len=64) :: digest
        character(len=8) :: date
        character(len=10) :: time
        if (present(known)) then
            digest = known
        else
            call file_sha256(deck, digest, error)
            if (allocated(error)) then
                error%category = input_error
                return
            end if
        end if
        call date_and_time(date, time)
        identity%run_id = date//'T'//time(1:6)//'-'//random_hex(16)
        identity%deck_sha256 = digest
        identity%deck_path = resolved_path(deck)
        identity%started = iso_timestamp()
        identity%host = host_name()
        identity%pid = process_id()
        identity%start_ticks = process_start_ticks(identity%pid)
    end subroutine new_run_identity

    !> The run id a text file of a result set carries ('' if none, or if it cannot be
    !> read): the word after a line's start '# cfrd run_id ' (CSV), '<!-- cfrd run_id '
    !> (XDMF) or ' RUN ID ' (the listings' banners) in one of its first lines.
    function text_run_id(path) result(run_id)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: run_id
        character(len=*), parameter :: markers(3) = [character(len=17) :: '# cfrd run_id ', &
                                                      '<!-- cfrd run_id ', ' RUN ID ']
        character(len=512) :: line
        integer :: unit, stat, k, m, at, ending
        run_id = ''
        ! A missing file is the usual case; asked first, as gfortran's failed OPEN loads the
        ! C library's locale data to word its message (docs/performance.md (ae)).
        if (.not. path_exists(path)) return
        open (newunit=unit, file=path, action='read', status='old', iostat=stat)
        if (stat /= 0) return
        do k = 1, header_lines
            read (unit, '(a)', iostat=stat) line
            if (stat /= 0) exit
            at = 0
            do m = 1, size(markers)
                ! the markers' trailing blanks are part of them: compare len_trim + 1
                if (line(:len_trim(markers(m)) + 1) == markers(m)(:len_trim(markers(m)) + 1)) &
                    at = len_trim(markers(m)) + 2
            end do
            if (at == 0) cycle
            line = adjustl(line(at:))
            ending = index(line, ' ') - 1
            if (ending > 0) run_id = line(:ending)
            exit
        end do
        close (unit)
    end function text_run_id
end module cfrd_run_identity
