!> Stage dates as day numbers (src/core/cfrd_dates.f90) against calendar facts.
module test_core_dates
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_dates, only: parse_date, days_from_civil
    implicit none
    private

    public :: collect_core_dates

contains

    subroutine collect_core_dates(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('day_numbers', test_day_numbers), &
                new_unittest('forms_and_rejections', test_forms) &
                ]
    end subroutine collect_core_dates

    !> 1970-01-01 is day 0; 2000-01-01 is day 10957 (30 years with 7 leap days: 30*365 + 7);
    !> 2000 is a leap year (2000-03-01 = 10957 + 31 + 29); 1900 was not.
    subroutine test_day_numbers(error)
        type(error_t), allocatable, intent(out) :: error
        call check(error, days_from_civil(1970, 1, 1), 0, '1970-01-01')
        if (allocated(error)) return
        call check(error, days_from_civil(2000, 1, 1), 10957, '2000-01-01')
        if (allocated(error)) return
        call check(error, days_from_civil(2000, 3, 1), 10957 + 60, '2000-03-01')
        if (allocated(error)) return
        call check(error, days_from_civil(1900, 3, 1) - days_from_civil(1900, 2, 1), 28, &
                   'February 1900')
        if (allocated(error)) return
        call check(error, days_from_civil(1969, 12, 31), -1, '1969-12-31')
    end subroutine test_day_numbers

    subroutine test_forms(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: a, b
        logical :: ok
        call parse_date(' 1997.05 ', a, ok)
        call check(error, ok, '1997.05 accepted')
        if (allocated(error)) return
        call parse_date('1997-05-15', b, ok)
        call check(error, ok, '1997-05-15 accepted')
        if (allocated(error)) return
        call check(error, b - a, 14.0_dp, '1997.05 is May 1st', abs=0.0_dp)
        if (allocated(error)) return
        call parse_date('1997-06', b, ok)
        call check(error, b - a, 31.0_dp, 'YYYY-MM: May has 31 days', abs=0.0_dp)
        if (allocated(error)) return
        call parse_date('1996-02-29', a, ok)
        call check(error, ok, '1996-02-29 (leap year) accepted')
        if (allocated(error)) return
        call parse_date('1997-02-29', a, ok)
        call check(error, .not. ok, '1997-02-29 rejected')
        if (allocated(error)) return
        call parse_date('1997.13', a, ok)
        call check(error, .not. ok, '1997.13 rejected')
        if (allocated(error)) return
        call parse_date('97.05', a, ok)
        call check(error, .not. ok, '97.05 rejected')
        if (allocated(error)) return
        call parse_date('May 1997', a, ok)
        call check(error, .not. ok, 'free text rejected')
    end subroutine test_forms
end module test_core_dates
