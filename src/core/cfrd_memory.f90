!> The C allocator's policy for a run. UMFPACK allocates and frees its numeric factorisation
!> at every factorisation; with glibc's defaults those blocks go to and come back from the
!> operating system each time (mmap above 128 KiB, heap trimming above 128 KiB free), and
!> the page faults cost a third of a small staged run (docs/performance.md, table d). Keeping
!> blocks up to 32 MiB on the heap and not trimming below 1 GiB avoids that. Larger blocks
!> (32 MiB is glibc's largest mmap threshold) come from the heap too, as mmap is not used at
!> all (M_MMAP_MAX 0): the x8 decks' factorisations (L + U 1.3e7 entries, about 160 MB) no
!> longer take their memory fresh, zeroed by the kernel, at each factorisation
!> (docs/performance.md (ad)).
module cfrd_memory
    use, intrinsic :: iso_c_binding, only: c_int
    implicit none
    private

    public :: tune_allocator

    integer(c_int), parameter :: m_trim_threshold = -1, m_mmap_threshold = -3, m_mmap_max = -4

    interface
        !> glibc's mallopt(3); returns 1 on success, 0 on error.
        integer(c_int) function mallopt(param, value) bind(C, name='mallopt')
            import :: c_int
            integer(c_int), value :: param, value
        end function mallopt
    end interface

contains

    !> Set the allocator thresholds; a refusal only costs speed, so it is ignored.
    subroutine tune_allocator()
        integer(c_int) :: status
        status = mallopt(m_mmap_threshold, 33554432_c_int)
        status = mallopt(m_trim_threshold, 1073741824_c_int)
        status = mallopt(m_mmap_max, 0_c_int)
    end subroutine tune_allocator
end module cfrd_memory
