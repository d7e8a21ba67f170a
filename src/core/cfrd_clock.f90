!> Wall-clock time for the figures the listing and the benchmark report.
module cfrd_clock
    use cfrd_kinds, only: dp, i8
    implicit none
    private

    public :: wall_seconds

contains

    !> Seconds since an arbitrary origin, from the 64-bit system clock.
    real(dp) function wall_seconds()
        integer(i8) :: count, rate
        call system_clock(count, rate)
        wall_seconds = real(count, dp)/real(rate, dp)
    end function wall_seconds
end module cfrd_clock
