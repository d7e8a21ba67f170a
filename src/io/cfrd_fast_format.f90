!> The text of numbers for the listing's long tables (issue 21): the same characters as
!> gfortran's formatted WRITE with the edit descriptors Iw, Fw.d and ESw.d, made by integer
!> arithmetic where they are provably the same and by an internal WRITE of the one field
!> elsewhere. A formatted WRITE costs about a microsecond a number in libgfortran, and the
!> listing's node, element and reaction tables (seven numbers a line, every node and
!> element, as the legacy codes print) took a tenth of a 10^4-quad run's CPU time
!> (docs/performance.md (r)); the legacy listing prints such tables after every stage.
!>
!> Why the fast text is the WRITE's: a real x is scaled by an exact power of ten (10^k,
!> |k| <= 22, is a double) in one multiplication or division, so that y = |x| 10^k carries a
!> relative error of at most 2^-53; with y below 10^9 that is below 1.2e-7 absolute. The
!> WRITE rounds the exact binary value to the nearest integer of y (gfortran's default
!> rounding: the C library's correctly rounded conversion). When the fraction of the computed
!> y is further than `margin` (1e-6) from one half, the exact value rounds to the same
!> integer: the fast text is taken (+0 is 0.0...0 and 0.0...0E+00). Otherwise (a tie or
!> near one), for -0 and negative values that round to zero (whose signs compilers print
!> differently), NaN, infinities, exponents beyond two digits and fields too narrow, the
!> field is written by an internal WRITE with the same descriptor, which is by definition
!> the WRITE's text.
!> test/test_io_fast_format.f90 holds every path against the intrinsic WRITE.
module cfrd_fast_format
    use, intrinsic :: iso_fortran_env, only: int64
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use cfrd_kinds, only: dp
    use cfrd_strings, only: to_text
    implicit none
    private

    public :: put_int, put_fixed, put_sci, put_text, end_line, next_line, write_lines
    public :: block_chars, line_max

    !> Tables are made in blocks of lines (next_line, write_lines) of at most line_max
    !> characters each with its line end, block_chars in all (4096 such lines).
    integer, parameter :: line_max = 128, block_chars = 4096*line_max

    !> Decision margin on the fraction of the scaled value, well above its error bound.
    real(dp), parameter :: margin = 1.0e-6_dp
    !> Scaled values at or above this go to the WRITE (their error bound nears the margin).
    real(dp), parameter :: y_max = 1.0e9_dp
    !> The powers of ten to 10^22, each a double exactly (10^k = 2^k 5^k and 5^22 < 2^53).
    real(dp), parameter :: pow10(0:22) = [1.0e0_dp, 1.0e1_dp, 1.0e2_dp, 1.0e3_dp, 1.0e4_dp, &
        1.0e5_dp, 1.0e6_dp, 1.0e7_dp, 1.0e8_dp, 1.0e9_dp, 1.0e10_dp, 1.0e11_dp, 1.0e12_dp, &
        1.0e13_dp, 1.0e14_dp, 1.0e15_dp, 1.0e16_dp, 1.0e17_dp, 1.0e18_dp, 1.0e19_dp, &
        1.0e20_dp, 1.0e21_dp, 1.0e22_dp]
    character(len=*), parameter :: digit_chars = '0123456789'

contains

    !> Append `text` to buf at pos (then advanced past it).
    pure subroutine put_text(buf, pos, text)
        character(len=*), intent(inout) :: buf
        integer, intent(inout) :: pos
        character(len=*), intent(in) :: text
        buf(pos:pos + len(text) - 1) = text
        pos = pos + len(text)
    end subroutine put_text

    !> Append a line end (the buffer's lines are written by one WRITE of '(a)').
    pure subroutine end_line(buf, pos)
        character(len=*), intent(inout) :: buf
        integer, intent(inout) :: pos
        buf(pos:pos) = new_line('a')
        pos = pos + 1
    end subroutine end_line

    !> Append n as the edit descriptor Iw writes it.
    pure subroutine put_int(buf, pos, n, w)
        character(len=*), intent(inout) :: buf
        integer, intent(inout) :: pos
        integer, intent(in) :: n, w
        character(len=24) :: digits
        integer :: first
        call unsigned_digits(abs(int(n, int64)), digits, first)
        if (n < 0) then
            first = first - 1
            digits(first:first) = '-'
        end if
        if (len(digits) - first + 1 > w) then
            write (buf(pos:pos + w - 1), '(i'//to_text(w)//')') n
        else
            call right_justify(buf(pos:pos + w - 1), digits(first:))
        end if
        pos = pos + w
    end subroutine put_int

    !> Append x as the edit descriptor Fw.d writes it (1 <= d <= 9).
    pure subroutine put_fixed(buf, pos, x, w, d)
        character(len=*), intent(inout) :: buf
        integer, intent(inout) :: pos
        real(dp), intent(in) :: x
        integer, intent(in) :: w, d
        character(len=32) :: text
        integer(int64) :: n, scale
        integer :: first, i
        logical :: ok
        ok = .false.
        first = len(text)
        if (ieee_is_finite(x) .and. d >= 1 .and. d <= 9) then
            call round_scaled(abs(x), d, n, ok)
            ! zeros, and negatives printed as zero, keep the WRITE's own sign rule
            if (ok) ok = n > 0 .or. (x == 0.0_dp .and. sign(1.0_dp, x) > 0.0_dp)
        end if
        if (ok) then
            scale = 10_int64**d
            text = ''
            call unsigned_digits(mod(n, scale) + scale, text, first)   ! 1 and d digits
            text(first:first) = '.'
            call unsigned_digits(n/scale, text(:first - 1), i)         ! the integer part
            first = i
        end if
        call place(buf, pos, x, w, d, 'f', ok, text, first)
    end subroutine put_fixed

    !> Append x as the edit descriptor ESw.d writes it (1 <= d <= 7).
    pure subroutine put_sci(buf, pos, x, w, d)
        character(len=*), intent(inout) :: buf
        integer, intent(inout) :: pos
        real(dp), intent(in) :: x
        integer, intent(in) :: w, d
        character(len=32) :: text
        integer(int64) :: n
        integer :: e10, k, tries, first
        real(dp) :: y, low, high
        logical :: ok
        ok = .false.
        first = len(text)
        if (x == 0.0_dp .and. d >= 1 .and. d <= 7) then
            if (sign(1.0_dp, x) > 0.0_dp) then       ! +0: 0.0...0E+00 (-0 to the WRITE)
                text = '0.'//repeat('0', d)//'E+00'
                text = adjustr(text)
                call place(buf, pos, x, w, d, 'es', .true., text, len(text) - d - 5)
                return
            end if
        else if (ieee_is_finite(x) .and. d >= 1 .and. d <= 7) then
            low = pow10(d)                  ! the d+1 digits of the mantissa: [low, high)
            high = pow10(d + 1)
            e10 = floor(log10(abs(x)))
            do tries = 1, 3
                k = d - e10
                if (abs(k) > 22) exit
                if (k >= 0) then
                    y = abs(x)*pow10(k)
                else
                    y = abs(x)/pow10(-k)
                end if
                ! the exponent is right when y rounds into [low, high); near the edges, WRITE
                if (abs(y - (low - 0.5_dp)) <= margin .or. abs(y - (high - 0.5_dp)) <= margin) exit
                if (y < low - 0.5_dp) then
                    e10 = e10 - 1
                else if (y >= high - 0.5_dp) then
                    e10 = e10 + 1
                else
                    call round_value(y, n, ok)
                    exit
                end if
            end do
            ok = ok .and. abs(e10) <= 99
        end if
        if (ok) then
            text = ''
            call unsigned_digits(n, text(:len(text) - 4), first)
            ! d1.d2...dp: shift the leading digit left of the point
            text(first - 1:first - 1) = text(first:first)
            text(first:first) = '.'
            first = first - 1
            text(len(text) - 3:len(text) - 3) = 'E'
            text(len(text) - 2:len(text) - 2) = merge('-', '+', e10 < 0)
            text(len(text) - 1:len(text) - 1) = digit_chars(abs(e10)/10 + 1:abs(e10)/10 + 1)
            text(len(text):len(text)) = digit_chars(mod(abs(e10), 10) + 1:mod(abs(e10), 10) + 1)
        end if
        call place(buf, pos, x, w, d, 'es', ok, text, first)
    end subroutine put_sci

    !> Put the unsigned text(first:) of x, its sign added, right-justified in the next w
    !> characters of buf when `ok` and it fits; else the internal WRITE of x with the
    !> descriptor `edit`w.d. Advances pos by w.
    pure subroutine place(buf, pos, x, w, d, edit, ok, text, first)
        character(len=*), intent(inout) :: buf
        integer, intent(inout) :: pos
        real(dp), intent(in) :: x
        integer, intent(in) :: w, d
        character(len=*), intent(in) :: edit
        logical, intent(in) :: ok
        character(len=*), intent(inout) :: text
        integer, intent(in) :: first
        integer :: start
        start = first
        if (ok) then            ! (x is finite then: no ordered comparison of a NaN)
            if (x < 0.0_dp) then
                start = first - 1
                text(start:start) = '-'
            end if
        end if
        if (ok .and. len(text) - start + 1 <= w) then
            call right_justify(buf(pos:pos + w - 1), text(start:))
        else
            write (buf(pos:pos + w - 1), '('//edit//to_text(w)//'.'//to_text(d)//')') x
        end if
        pos = pos + w
    end subroutine place

    !> End the line being made in buf; write the block to unit when it is full. With
    !> `stat` (and `msg`), the WRITE's iostat: nothing is written once it is not 0.
    subroutine next_line(unit, buf, pos, stat, msg)
        integer, intent(in) :: unit
        character(len=*), intent(inout) :: buf
        integer, intent(inout) :: pos
        integer, intent(inout), optional :: stat
        character(len=*), intent(inout), optional :: msg
        call end_line(buf, pos)
        if (pos > len(buf) - line_max) call write_lines(unit, buf, pos, stat, msg)
    end subroutine next_line

    !> Write the lines made in buf(1:pos-1), each ended by a line end, as one record whose
    !> own end is the last line's, and empty buf; nothing when there are none.
    subroutine write_lines(unit, buf, pos, stat, msg)
        integer, intent(in) :: unit
        character(len=*), intent(in) :: buf
        integer, intent(inout) :: pos
        integer, intent(inout), optional :: stat
        character(len=*), intent(inout), optional :: msg
        if (pos > 1) then
            if (.not. present(stat)) then
                write (unit, '(a)') buf(1:pos - 2)
            else if (stat == 0) then
                write (unit, '(a)', iostat=stat, iomsg=msg) buf(1:pos - 2)
            end if
        end if
        pos = 1
    end subroutine write_lines

    !> n = |x| 10^d rounded to the nearest integer, ok when that is certain (see the module).
    pure subroutine round_scaled(ax, d, n, ok)
        real(dp), intent(in) :: ax
        integer, intent(in) :: d
        integer(int64), intent(out) :: n
        logical, intent(out) :: ok
        n = 0
        ok = ax < y_max/pow10(d)        ! (and no overflow in the product)
        if (ok) call round_value(ax*pow10(d), n, ok)
    end subroutine round_scaled

    !> n = y rounded to the nearest integer; ok unless y is at or above y_max or its
    !> fraction lies within `margin` of one half.
    pure subroutine round_value(y, n, ok)
        real(dp), intent(in) :: y
        integer(int64), intent(out) :: n
        logical, intent(out) :: ok
        real(dp) :: whole, fraction
        n = 0
        ok = y < y_max
        if (.not. ok) return
        whole = aint(y)
        fraction = y - whole
        ok = abs(fraction - 0.5_dp) > margin
        n = int(whole, int64)
        if (fraction > 0.5_dp) n = n + 1
    end subroutine round_value

    !> The decimal digits of m (>= 0) right-aligned in text; first: where they start.
    pure subroutine unsigned_digits(m, text, first)
        integer(int64), intent(in) :: m
        character(len=*), intent(inout) :: text
        integer, intent(out) :: first
        integer(int64) :: rest
        integer :: r
        rest = m
        first = len(text) + 1
        do
            first = first - 1
            r = int(mod(rest, 10_int64))
            text(first:first) = digit_chars(r + 1:r + 1)
            rest = rest/10
            if (rest == 0) exit
        end do
    end subroutine unsigned_digits

    pure subroutine right_justify(field, text)
        character(len=*), intent(out) :: field
        character(len=*), intent(in) :: text
        field = repeat(' ', len(field) - len(text))//text
    end subroutine right_justify
end module cfrd_fast_format
