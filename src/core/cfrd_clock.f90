!> Wall-clock time for the figures the listing and the benchmark report, and the date and
!> time of day as results record them.
module cfrd_clock
    use cfrd_kinds, only: dp, i8
    implicit none
    private

    public :: wall_seconds, iso_timestamp

contains

    !> Seconds since an arbitrary origin, from the 64-bit system clock.
    real(dp) function wall_seconds()
        integer(i8) :: count, rate
        call system_clock(count, rate)
        wall_seconds = real(count, dp)/real(rate, dp)
    end function wall_seconds

    !> The local date and time in ISO 8601 with the zone: '2026-11-25T08:23:02+01:00'.
    function iso_timestamp() result(text)
        character(len=:), allocatable :: text
        character(len=8) :: date
        character(len=10) :: time
        character(len=5) :: zone
        call date_and_time(date, time, zone)
        text = date(1:4)//'-'//date(5:6)//'-'//date(7:8)//'T'//time(1:2)//':'//time(3:4)// &
               ':'//time(5:6)//zone(1:3)//':'//zone(4:5)
    end function iso_timestamp
end module cfrd_clock
