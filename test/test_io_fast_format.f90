!> The listing's number text (src/io/cfrd_fast_format.f90) against the reference it must
!> equal character for character: gfortran's intrinsic formatted WRITE with the same edit
!> descriptor (libgfortran's conversion, an implementation independent of the module's
!> integer arithmetic). The values: the edge cases of every path (zeros of both signs,
!> exact ties such as 0.125 and 2.5, values a unit of the last place either side of a
!> rounding tie, the mantissa's carry to the next exponent as 9.9999995, exponents of two
!> and three digits, NaN, infinities, the largest and smallest doubles, fields too narrow)
!> and 200,000 pseudo-random values over 60 decades for each descriptor of the listing's
!> tables, with half of them placed on or next to a decimal tie of that descriptor.
module test_io_fast_format
    use, intrinsic :: iso_fortran_env, only: int64
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf, &
                                              ieee_negative_inf
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error
    use cfrd_testing, only: unittest_t, new_unittest
    use cfrd_fast_format, only: put_int, put_fixed, put_sci
    implicit none
    private

    public :: collect_io_fast_format

    !> The descriptors of the listing's tables (cfrd_listing: nodes i7,2f15.4,4es15.6;
    !> elements i7,i4,6es13.4,f8.2; reactions i7,2es15.6) and two more widths.
    integer, parameter :: n_sci = 4, n_fixed = 3
    integer, parameter :: sci_w(n_sci) = [15, 13, 10, 12], sci_d(n_sci) = [6, 4, 2, 3]
    integer, parameter :: fixed_w(n_fixed) = [15, 8, 10], fixed_d(n_fixed) = [4, 2, 3]

contains

    subroutine collect_io_fast_format(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('edge_cases_as_write', test_edges), &
                new_unittest('random_values_as_write', test_random), &
                new_unittest('integers_as_write', test_integers) &
                ]
    end subroutine collect_io_fast_format

    subroutine test_edges(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: values(:)
        real(dp) :: base(34)
        integer :: i
        base = [0.0_dp, 0.5_dp, 1.5_dp, 2.5_dp, 0.125_dp, 0.375_dp, 1.0_dp, 10.0_dp, &
                5.0e-5_dp, 4.999e-5_dp, 5.0e-3_dp, 0.015_dp, 0.025_dp, 9.9999995_dp, &
                9.99999949_dp, 99999.995_dp, 0.99999995_dp, 9999999.5_dp, 999.99995_dp, &
                1.0e22_dp, 1.0e23_dp, 1.0e99_dp, 9.9999996e99_dp, 9.99999949e99_dp, 1.0e100_dp, &
                1.0e-99_dp, 9.99999951e-100_dp, 1.0e-100_dp, 1.0e-300_dp, tiny(1.0_dp), &
                tiny(1.0_dp)/1024, huge(1.0_dp), 123456789.12345_dp, 1.0e9_dp]
        values = [base, -base, [(nearest(base(i), 1.0_dp), nearest(base(i), -1.0_dp), &
                                 i = 2, size(base) - 4)], &
                  ieee_value(1.0_dp, ieee_quiet_nan), ieee_value(1.0_dp, ieee_positive_inf), &
                  ieee_value(1.0_dp, ieee_negative_inf)]
        do i = 1, size(values)
            call check_value(values(i), error)
            if (allocated(error)) return
        end do
    end subroutine test_edges

    subroutine test_random(error)
        type(error_t), allocatable, intent(out) :: error
        integer(int64) :: state
        integer :: i, k
        real(dp) :: x, u
        state = 20261127_int64
        do i = 1, 200000
            u = uniform(state)
            x = (1.0_dp + 9.0_dp*uniform(state))*10.0_dp**(floor(60.0_dp*u) - 30)
            if (uniform(state) < 0.5_dp) x = -x
            if (mod(i, 2) == 0) then
                ! on or next to a tie of one descriptor: (m + 1/2) 10^-d, then a few ulps off
                k = 1 + mod(i/2, 4)
                x = (aint(abs(x)*10.0_dp**sci_d(k)) + 0.5_dp)/10.0_dp**sci_d(k)
                if (mod(i, 6) == 0) x = nearest(x, 1.0_dp)
                if (mod(i, 8) == 0) x = nearest(x, -1.0_dp)
            end if
            call check_value(x, error)
            if (allocated(error)) return
        end do
    end subroutine test_random

    subroutine test_integers(error)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: widths(3) = [7, 4, 12]
        integer :: values(14), i, j, pos
        character(len=16) :: mine, reference
        character(len=8) :: form
        values = [0, 1, -1, 9, 10, 999, 1000, -999, 9999, 99999, 999999, 1234567, -123456, &
                  huge(1)]
        do j = 1, size(widths)
            write (form, '(a,i0,a)') '(i', widths(j), ')'
            do i = 1, size(values)
                mine = ''
                pos = 1
                call put_int(mine, pos, values(i), widths(j))
                reference = ''
                write (reference, form) values(i)
                if (mine /= reference .or. pos /= widths(j) + 1) then
                    call fatal_error(error, 'put_int '//trim(form)//': "'// &
                                     mine(1:widths(j))//'" against WRITE "'// &
                                     reference(1:widths(j))//'"')
                    return
                end if
            end do
        end do
    end subroutine test_integers

    !> x through every descriptor, put_* against the intrinsic WRITE.
    subroutine check_value(x, error)
        real(dp), intent(in) :: x
        type(error_t), allocatable, intent(out) :: error
        character(len=24) :: mine, reference
        character(len=16) :: form
        integer :: k, pos, w, d
        do k = 1, n_sci + n_fixed
            mine = ''
            pos = 1
            if (k <= n_sci) then
                w = sci_w(k)
                d = sci_d(k)
                write (form, '(a,i0,a,i0,a)') '(es', w, '.', d, ')'
                call put_sci(mine, pos, x, w, d)
            else
                w = fixed_w(k - n_sci)
                d = fixed_d(k - n_sci)
                write (form, '(a,i0,a,i0,a)') '(f', w, '.', d, ')'
                call put_fixed(mine, pos, x, w, d)
            end if
            reference = ''
            write (reference, form) x
            if (mine /= reference .or. pos /= w + 1) then
                call fail(x, form, mine, reference, error)
                return
            end if
        end do
    end subroutine check_value

    subroutine fail(x, form, mine, reference, error)
        real(dp), intent(in) :: x
        character(len=*), intent(in) :: form, mine, reference
        type(error_t), allocatable, intent(out) :: error
        character(len=32) :: exact
        write (exact, '(es32.20)') x
        call fatal_error(error, trim(form)//' of '//trim(adjustl(exact))//': "'//trim(mine)// &
                         '" against WRITE "'//trim(reference)//'"')
    end subroutine fail

    !> A uniform number in [0, 1): Marsaglia's xorshift64 (13, 7, 17), the top 53 bits.
    real(dp) function uniform(state)
        integer(int64), intent(inout) :: state
        state = ieor(state, ishft(state, 13))
        state = ieor(state, ishft(state, -7))
        state = ieor(state, ishft(state, 17))
        uniform = real(ishft(state, -11), dp)*2.0_dp**(-53)
    end function uniform
end module test_io_fast_format
