!> Tests of the parallel regions run in place (cfrd_omp_in_place.c, cfrd_omp_threads): a
!> region that gets one thread runs on the caller without a team, one that gets two runs in
!> libgomp's team of two (CHOLMOD's regions: test_solver_cholmod). The reference of every
!> sum is its closed form, n (n + 1) / 2.
module test_core_omp
    use, intrinsic :: iso_c_binding, only: c_long_long
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_omp_threads, only: regions_in_place, begin_serial_library, end_serial_library
    !$ use omp_lib, only: omp_get_num_threads, omp_set_num_threads, &
    !$                    omp_get_max_threads, omp_set_dynamic
    implicit none
    private

    public :: collect_core_omp

    integer, parameter :: n = 100000

contains

    subroutine collect_core_omp(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('one_thread_region_in_place', test_one_thread), &
                new_unittest('serial_library_region_in_place', test_serial_library), &
                new_unittest('two_thread_region_in_a_team', test_two_threads) &
                ]
    end subroutine collect_core_omp

    !> Sum 1..n in a parallel region with a worksharing loop and a reduction; returns the
    !> sum and the region's thread count. `ask` > 0 names the count in the construct.
    subroutine region_sum(ask, total, threads)
        integer, intent(in) :: ask
        integer(c_long_long), intent(out) :: total
        integer, intent(out) :: threads
        total = 0
        threads = 1
        if (ask > 0) then
            !$omp parallel num_threads(ask) shared(total, threads)
            call region_body(total, threads)
            !$omp end parallel
        else
            !$omp parallel shared(total, threads)
            call region_body(total, threads)
            !$omp end parallel
        end if
    end subroutine region_sum

    !> The region's work, orphaned constructs binding to the caller's region: the sum of
    !> 1..n shared out, and the team's size.
    subroutine region_body(total, threads)
        integer(c_long_long), intent(inout) :: total
        integer, intent(inout) :: threads
        integer :: i
        !$omp do schedule(dynamic, 1000) reduction(+:total)
        do i = 1, n
            total = total + i
        end do
        !$omp end do
        !$omp single
        !$ threads = omp_get_num_threads()
        !$omp end single
    end subroutine region_body

    !> Sum 1..n in a region that asks for `ask` threads (0: no count named) and check the
    !> team's size, the regions run in place (0 or 1; none built without OpenMP, where the
    !> directives are comments) and the sum against n (n + 1) / 2.
    subroutine check_region(ask, threads_expected, in_place_expected, error)
        integer, intent(in) :: ask, threads_expected, in_place_expected
        type(error_t), allocatable, intent(out) :: error
        integer(c_long_long) :: before, total
        integer :: threads, in_place
        in_place = 0
        !$ in_place = in_place_expected
        before = regions_in_place()
        call region_sum(ask, total, threads)
        call check(error, threads, threads_expected, 'threads of the region')
        if (allocated(error)) return
        call check(error, int(regions_in_place() - before), in_place, &
                   'regions run in place')
        if (allocated(error)) return
        call check(error, real(total, dp), real(n, dp)*(n + 1)/2, 'sum 1..n against n (n+1)/2')
    end subroutine check_region

    !> With one thread (cfrd's default) a region that names no count runs in place.
    subroutine test_one_thread(error)
        type(error_t), allocatable, intent(out) :: error
        integer :: saved
        saved = 1
        !$ saved = omp_get_max_threads()
        !$ call omp_set_num_threads(1)
        call check_region(0, 1, 1, error)
        !$ call omp_set_num_threads(saved)
    end subroutine test_one_thread

    !> With no active level allowed (begin_serial_library), a region that asks for four
    !> threads runs in place on one.
    subroutine test_serial_library(error)
        type(error_t), allocatable, intent(out) :: error
        integer :: saved
        saved = begin_serial_library()
        call check_region(4, 1, 1, error)
        call end_serial_library(saved)
    end subroutine test_serial_library

    !> A region that asks for two threads gets libgomp's team of two (not counted), with the
    !> same sum. Without OpenMP the loop runs on one thread.
    subroutine test_two_threads(error)
        type(error_t), allocatable, intent(out) :: error
        integer :: expected_threads
        expected_threads = 1
        !$ expected_threads = 2
        !$ call omp_set_dynamic(.false.)
        call check_region(2, expected_threads, 0, error)
    end subroutine test_two_threads
end module test_core_omp
