!> Working precision and the few physical constants that are not material data.
module cfrd_kinds
    use, intrinsic :: iso_fortran_env, only: real64, int64
    implicit none
    private

    public :: dp, i8

    !> Double precision for every real in cfrd.
    integer, parameter :: dp = real64
    !> 64-bit integer, for byte and nonzero counts that can pass 2**31.
    integer, parameter :: i8 = int64
end module cfrd_kinds
