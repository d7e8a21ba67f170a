!> Calendar dates of stages as day numbers, so that time-dependent laws see the time
!> between stages (docs/cards.md, STAGES; docs/theory.md section 15). Accepted forms:
!> `YYYY-MM-DD`, `YYYY.MM` and `YYYY-MM` (a month stands for its first day [choice]).
module cfrd_dates
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: parse_date, days_from_civil, date_forms

    !> The forms, for messages ("expected ...").
    character(len=*), parameter :: date_forms = 'a date YYYY-MM-DD, YYYY.MM or YYYY-MM'

contains

    !> Day number of a proleptic Gregorian date (days since 1970-01-01), after
    !> H. Hinnant's days_from_civil algorithm.
    pure integer function days_from_civil(year, month, day) result(days)
        integer, intent(in) :: year, month, day
        integer :: y, era, yoe, doy, doe, mp
        y = year
        if (month <= 2) y = y - 1
        era = y/400
        if (y < 0 .and. mod(y, 400) /= 0) era = era - 1
        yoe = y - era*400
        mp = mod(month + 9, 12)
        doy = (153*mp + 2)/5 + day - 1
        doe = yoe*365 + yoe/4 - yoe/100 + doy
        days = era*146097 + doe - 719468
    end function days_from_civil

    !> The day number of `text` (leading and trailing blanks ignored) in `day`; `ok` is
    !> false for anything but the accepted forms or an impossible date (month 13, April 31,
    !> February 29 of a common year); years 1000 to 9999.
    pure subroutine parse_date(text, day, ok)
        character(len=*), intent(in) :: text
        real(dp), intent(out) :: day
        logical, intent(out) :: ok
        character(len=:), allocatable :: t
        integer :: year, month, dom
        day = 0.0_dp
        ok = .false.
        t = trim(adjustl(text))
        if (len(t) == 7) then
            if (t(5:5) /= '.' .and. t(5:5) /= '-') return
            if (.not. (digits(t(1:4)) .and. digits(t(6:7)))) return
            dom = 1
        else if (len(t) == 10) then
            if (t(5:5) /= '-' .or. t(8:8) /= '-') return
            if (.not. (digits(t(1:4)) .and. digits(t(6:7)) .and. digits(t(9:10)))) return
            read (t(9:10), '(i2)') dom
        else
            return
        end if
        read (t(1:4), '(i4)') year
        read (t(6:7), '(i2)') month
        if (year < 1000 .or. month < 1 .or. month > 12) return
        if (dom < 1 .or. dom > month_length(year, month)) return
        day = real(days_from_civil(year, month, dom), dp)
        ok = .true.
    end subroutine parse_date

    pure logical function digits(s)
        character(len=*), intent(in) :: s
        digits = verify(s, '0123456789') == 0
    end function digits

    pure integer function month_length(year, month) result(n)
        integer, intent(in) :: year, month
        integer, parameter :: lengths(12) = [31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31]
        n = lengths(month)
        if (month == 2 .and. (mod(year, 4) == 0 .and. (mod(year, 100) /= 0 .or. &
                                                       mod(year, 400) == 0))) n = 29
    end function month_length
end module cfrd_dates
