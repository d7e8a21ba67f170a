!> Card images: reading a deck into cards with their line numbers, cutting fields by column
!> (fixed format) or by comma (free format, column 1 = '&'), and strict parsing of integer,
!> real and text fields. Every problem becomes one message that names the file, line, column
!> range and field: `dam.dat:37:1-10: field E of MATERIALS 3: expected a real > 0, found '-3e4'`.
!> A card layout is data (an array of `field_t`), so new cards need no new parsing code.
module cfrd_cards
    use, intrinsic :: iso_c_binding, only: c_char, c_double, c_ptr, c_null_char, c_null_ptr
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, input_error
    use cfrd_strings, only: to_text
    implicit none
    private

    public :: card_t, field_t, deck_lines_t
    public :: int_field, real_field, text_field, card_columns
    public :: found_text, found_value, found_blank, found_upper, default_pa
    public :: read_deck_lines, classify_line, field_text, get_int, get_real, get_text
    public :: field_error, card_error, line_error, upper, is_comment, is_real, to_text

    !> The UTF-8 byte-order mark, skipped at the start of a deck.
    character(len=*), parameter :: utf8_bom = achar(239)//achar(187)//achar(191)

    !> Width of a fixed-format card.
    integer, parameter :: card_columns = 80
    !> The columns of the EFFECTS card (eight switches after its keyword).
    integer, parameter :: effects_columns = 90

    integer, parameter :: int_field = 1, real_field = 2, text_field = 3

    !> Power of ten that no real field may reach (docs/cards.md).
    integer, parameter :: max_magnitude = 20

    !> What a failed check of a field quotes after "found": the field's text, the integer
    !> read, the text or '(blank)', the text in upper case.
    integer, parameter :: found_text = 1, found_value = 2, found_blank = 3, found_upper = 4

    !> `default_from` of a field whose blank takes a multiple of the atmospheric pressure PA.
    integer, parameter :: default_pa = -1

    !> One field of a card layout: name, first column, width, kind, and what the card schema
    !> (cfrd_card_schema) checks of it; the defaults check nothing.
    type :: field_t
        character(len=10) :: name = ''
        integer :: first = 1
        integer :: width = 0
        integer :: kind = int_field
        !> The value of a blank field (a whole number for an integer field), or, with
        !> `default_from` k > 0, field k's value times `default_scale` (default_pa: PA's).
        real(dp) :: default = 0.0_dp
        integer :: default_from = 0
        real(dp) :: default_scale = 1.0_dp
        logical :: required = .false.   !! blank is an error (found '')
        !> Limits of a number: lo <= value <= hi, or < where open.
        real(dp) :: lo = -huge(1.0_dp), hi = huge(1.0_dp)
        logical :: lo_open = .false., hi_open = .false.
        !> A text field with words: the words accepted (blank-separated, compared in upper
        !> case); its value is the word's position, a blank field's `default` (0: required).
        character(len=40) :: words = ''
        !> The words of the message after "expected"; blank: no check.
        character(len=100) :: expected = ''
        integer :: found = found_text
    end type field_t

    !> One card: where it came from and its text; free-format cards keep their comma tokens.
    type :: card_t
        integer :: line = 0
        character(len=:), allocatable :: text
        logical :: free = .false.
        integer, allocatable :: token_first(:), token_last(:)  !! columns of free tokens
    end type card_t

    !> A deck file as lines.
    type :: deck_lines_t
        character(len=:), allocatable :: file
        character(len=:), allocatable :: text      !! the whole file, CR removed
        integer, allocatable :: first(:), last(:)  !! each line's span in text
    end type deck_lines_t

    interface
        !> C's correctly rounded decimal-to-binary conversion; far faster than a Fortran
        !> internal list-directed read, which dominated the reading of large decks.
        real(c_double) function c_strtod(text, end) bind(C, name='strtod')
            import :: c_char, c_double, c_ptr
            character(kind=c_char), intent(in) :: text(*)
            type(c_ptr), value :: end
        end function c_strtod
    end interface

contains

    !> Read a whole file; split it into lines (LF or CRLF). An unreadable file is an error.
    subroutine read_deck_lines(path, deck, error, text)
        character(len=*), intent(in) :: path
        type(deck_lines_t), intent(out) :: deck
        type(error_t), allocatable, intent(out) :: error
        !> the deck's text, read from elsewhere (a results file's /input/deck): `path` only
        !> names it
        character(len=*), intent(in), optional :: text
        character(len=:), allocatable :: raw
        integer :: unit, stat, size_bytes, i, n, start, k, first_byte
        logical :: exists
        character(len=256) :: msg

        deck%file = path
        if (present(text)) then
            raw = text
        else
            call read_file_bytes(error)
            if (allocated(error)) return
        end if

        ! Drop a UTF-8 byte-order mark (editors on Windows save one) and carriage returns
        ! (CRLF files), and count lines.
        allocate (character(len=len(raw)) :: deck%text)
        k = 0
        n = 0
        first_byte = 1
        if (len(raw) >= 3) then
            if (raw(1:3) == utf8_bom) first_byte = 4
        end if
        do i = first_byte, len(raw)
            if (raw(i:i) == achar(13)) cycle
            k = k + 1
            deck%text(k:k) = raw(i:i)
            if (raw(i:i) == achar(10)) n = n + 1
        end do
        deck%text = deck%text(1:k)
        if (k > 0) then
            if (deck%text(k:k) /= achar(10)) n = n + 1
        end if
        allocate (deck%first(n), deck%last(n))
        start = 1
        n = 0
        do i = 1, k
            if (deck%text(i:i) == achar(10)) then
                n = n + 1
                deck%first(n) = start
                deck%last(n) = i - 1
                start = i + 1
            end if
        end do
        if (start <= k) then
            n = n + 1
            deck%first(n) = start
            deck%last(n) = k
        end if
    contains
        subroutine read_file_bytes(error)
            type(error_t), allocatable, intent(out) :: error
            inquire (file=path, exist=exists, size=size_bytes)
            if (.not. exists) then
                call fatal_error(error, path//': no such deck file', input_error)
                return
            end if
            allocate (character(len=max(size_bytes, 0)) :: raw)
            if (size_bytes > 0) then
                open (newunit=unit, file=path, access='stream', form='unformatted', &
                      status='old', action='read', iostat=stat, iomsg=msg)
                if (stat /= 0) then
                    call fatal_error(error, path//': cannot open the deck: '//trim(msg), &
                                     input_error)
                    return
                end if
                read (unit, iostat=stat, iomsg=msg) raw
                close (unit)
                if (stat /= 0) then
                    call fatal_error(error, path//': cannot read the deck: '//trim(msg), &
                                     input_error)
                    return
                end if
            end if
        end subroutine read_file_bytes
    end subroutine read_deck_lines

    !> Comment cards: '*' in column 1, 'C' alone or followed by a blank; blank lines too.
    pure logical function is_comment(text)
        character(len=*), intent(in) :: text
        if (len_trim(text) == 0) then
            is_comment = .true.
        else if (text(1:1) == '*') then
            is_comment = .true.
        else if (text(1:1) == 'C' .or. text(1:1) == 'c') then
            if (len(text) == 1) then
                is_comment = .true.
            else
                is_comment = text(2:2) == ' '
            end if
        else
            is_comment = .false.
        end if
    end function is_comment

    !> Make a card of line `line` (text without its line end): free format when column 1 is
    !> '&' (tokens split at commas), else fixed format, checked for tabs and for text beyond
    !> column 80.
    subroutine classify_line(file, line, text, card, error)
        character(len=*), intent(in) :: file, text
        integer, intent(in) :: line
        type(card_t), intent(out) :: card
        type(error_t), allocatable, intent(out) :: error
        integer :: i, n, start, tab, limit
        card%line = line
        if (text(1:1) == '&') then
            card%free = .true.
            card%text = text
            n = 1
            do i = 2, len(text)
                if (text(i:i) == ',') n = n + 1
            end do
            allocate (card%token_first(n), card%token_last(n))
            start = 2
            n = 0
            do i = 2, len(text) + 1
                if (i == len(text) + 1) then
                    n = n + 1
                    card%token_first(n) = start
                    card%token_last(n) = i - 1
                else if (text(i:i) == ',') then
                    n = n + 1
                    card%token_first(n) = start
                    card%token_last(n) = i - 1
                    start = i + 1
                end if
            end do
            return
        end if
        tab = index(text, achar(9))
        if (tab > 0) then
            call line_error(error, file, line, tab, tab, 'a tab character on a fixed-format '// &
                            'card: columns cannot be counted; use blanks (or an & card)')
            return
        end if
        ! The EFFECTS card of CONTROL alone runs to column 90 (its eighth switch, CREEP).
        limit = card_columns
        if (len(text) >= 7) then
            if (upper(text(1:7)) == 'EFFECTS') limit = effects_columns
        end if
        if (len(text) > limit) then
            if (len_trim(text(limit + 1:)) > 0) then
                call line_error(error, file, line, limit + 1, len_trim(text), &
                                'text beyond column '//to_text(limit)// &
                                ' on a fixed-format card: '// &
                                "found '"//trim(text(limit + 1:))// &
                                "' (use an & card for longer lines)")
                return
            end if
        end if
        card%text = text
    end subroutine classify_line

    !> The text of field `k` of a layout on a card, and its column range; blank if absent.
    subroutine field_text(card, fields, k, text, first, last)
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        character(len=:), allocatable, intent(out) :: text
        integer, intent(out) :: first, last
        if (card%free) then
            if (k <= size(card%token_first)) then
                ! Report the columns of the token without its surrounding blanks.
                first = card%token_first(k)
                last = card%token_last(k)
                ! A trailing free-text field (a LABEL) takes the rest of the card, commas
                ! included.
                if (k == size(fields) .and. is_free_text(fields(k))) last = len(card%text)
                ! (Fortran's .and. does not short-circuit: test the bounds first.)
                do while (first < last)
                    if (card%text(first:first) /= ' ') exit
                    first = first + 1
                end do
                do while (last > first)
                    if (card%text(last:last) /= ' ') exit
                    last = last - 1
                end do
                if (last < first) then
                    ! An empty token: '&1,,3' or a trailing comma.
                    last = first
                    text = ''
                else
                    text = card%text(first:last)
                end if
            else
                first = len(card%text) + 1
                last = first
                text = ''
            end if
        else
            first = fields(k)%first
            last = fields(k)%first + fields(k)%width - 1
            if (first > len(card%text)) then
                text = ''
            else
                text = card%text(first:min(last, len(card%text)))
            end if
        end if
    end subroutine field_text

    !> Integer field k: `value` (default when blank); `given` says whether it was not blank.
    subroutine get_int(file, card, fields, k, context, default, value, error, given)
        character(len=*), intent(in) :: file, context
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k, default
        integer, intent(out) :: value
        type(error_t), allocatable, intent(out) :: error
        logical, intent(out), optional :: given
        character(len=:), allocatable :: text
        integer :: first, last
        if (card%free) then
            call check_extra_tokens(file, card, fields, context, error)
            if (allocated(error)) return
        end if
        call field_text(card, fields, k, text, first, last)
        if (present(given)) given = len_trim(text) > 0
        value = default
        if (len_trim(text) == 0) return
        if (.not. is_integer(trim(adjustl(text)))) then
            call field_error(error, file, card, fields, k, context, 'an integer', text)
            return
        end if
        value = parse_integer(trim(adjustl(text)))
    end subroutine get_int

    !> Real field k (Fortran syntax, E or D exponent); default when blank.
    subroutine get_real(file, card, fields, k, context, default, value, error, given)
        character(len=*), intent(in) :: file, context
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        real(dp), intent(in) :: default
        real(dp), intent(out) :: value
        type(error_t), allocatable, intent(out) :: error
        logical, intent(out), optional :: given
        character(len=:), allocatable :: text, number
        integer :: first, last, i
        if (card%free) then
            call check_extra_tokens(file, card, fields, context, error)
            if (allocated(error)) return
        end if
        call field_text(card, fields, k, text, first, last)
        if (present(given)) given = len_trim(text) > 0
        value = default
        if (len_trim(text) == 0) return
        number = trim(adjustl(text))
        if (.not. is_real(number)) then
            call field_error(error, file, card, fields, k, context, 'a real number', text)
            return
        end if
        ! Refuse magnitudes no deck in kN, m and kPa needs: near 1e308 strtod overflows,
        ! and a field of 1e307 (a unit weight, a modulus, PA) overflowed in the analysis
        ! (found by tools/fuzz.py). Products of two fields below 1e20 stay finite.
        if (decimal_magnitude(number) >= max_magnitude) then
            call field_error(error, file, card, fields, k, context, &
                             'a real number of magnitude below 1e20', text)
            return
        end if
        do i = 1, len(number)
            if (number(i:i) == 'd' .or. number(i:i) == 'D') number(i:i) = 'e'
        end do
        value = c_strtod(number//c_null_char, c_null_ptr)
    end subroutine get_real

    !> A free-format card may not carry more fields than its layout: a non-blank token after
    !> the last field is an error (it usually means a field was inserted by mistake, and
    !> every value after it is shifted). Blank extra tokens (a trailing comma) are harmless.
    subroutine check_extra_tokens(file, card, fields, context, error)
        character(len=*), intent(in) :: file, context
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        type(error_t), allocatable, intent(out) :: error
        integer :: t, first, last
        if (is_free_text(fields(size(fields)))) return   ! it takes the rest of the card
        do t = size(fields) + 1, size(card%token_first)
            first = card%token_first(t)
            last = card%token_last(t)
            if (last < first) cycle
            if (len_trim(card%text(first:last)) == 0) cycle
            do while (card%text(first:first) == ' ')
                first = first + 1
            end do
            last = first + len_trim(card%text(first:card%token_last(t))) - 1
            call line_error(error, file, card%line, first, last, 'field after '// &
                            trim(fields(size(fields))%name)//' of '//context// &
                            ': expected no more fields (the card has '// &
                            to_text(size(fields))//"), found '"//card%text(first:last)//"'")
            return
        end do
    end subroutine check_extra_tokens

    !> A text field wider than A10 is free text (a LABEL), not a name.
    pure logical function is_free_text(field)
        type(field_t), intent(in) :: field
        is_free_text = field%kind == text_field .and. field%width > 10
    end function is_free_text

    !> Text field k, blanks trimmed at both ends.
    subroutine get_text(card, fields, k, value)
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        character(len=:), allocatable, intent(out) :: value
        character(len=:), allocatable :: text
        integer :: first, last
        call field_text(card, fields, k, text, first, last)
        value = trim(adjustl(text))
    end subroutine get_text

    !> `file:line:c1-c2: field NAME of CONTEXT: expected WHAT, found 'TEXT'`.
    subroutine field_error(error, file, card, fields, k, context, expected, found)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: file, context, expected, found
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        character(len=:), allocatable :: text
        integer :: first, last
        call field_text(card, fields, k, text, first, last)
        call line_error(error, file, card%line, first, last, 'field '//trim(fields(k)%name)// &
                        ' of '//context//': expected '//expected//", found '"// &
                        trim(adjustl(found))//"'")
    end subroutine field_error

    !> `file:line: message` for a problem of a whole card.
    subroutine card_error(error, file, card, message)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: file, message
        type(card_t), intent(in) :: card
        call fatal_error(error, file//':'//to_text(card%line)//': '//message, input_error)
    end subroutine card_error

    !> `file:line:c1-c2: message`.
    subroutine line_error(error, file, line, first, last, message)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: file, message
        integer, intent(in) :: line, first, last
        call fatal_error(error, file//':'//to_text(line)//':'//to_text(first)//'-'// &
                         to_text(last)//': '//message, input_error)
    end subroutine line_error

    !> The value of a string that `is_integer` accepted (at most 9 digits: no overflow).
    pure integer function parse_integer(s) result(value)
        character(len=*), intent(in) :: s
        integer :: i, start
        start = 1
        if (s(1:1) == '+' .or. s(1:1) == '-') start = 2
        value = 0
        do i = start, len(s)
            value = 10*value + (iachar(s(i:i)) - iachar('0'))
        end do
        if (s(1:1) == '-') value = -value
    end function parse_integer

    !> [sign] digits (at most 9), nothing else.
    pure logical function is_integer(s)
        character(len=*), intent(in) :: s
        integer :: i, start
        is_integer = .false.
        if (len(s) == 0) return
        start = 1
        if (s(1:1) == '+' .or. s(1:1) == '-') start = 2
        if (start > len(s)) return
        if (len(s) - start + 1 > 9) return
        do i = start, len(s)
            if (s(i:i) < '0' .or. s(i:i) > '9') return
        end do
        is_integer = .true.
    end function is_integer

    !> [sign] (digits [. [digits]] | . digits) [(E|D) [sign] digits], nothing else.
    pure logical function is_real(s)
        character(len=*), intent(in) :: s
        integer :: i, mantissa_digits, exponent_digits
        logical :: seen_dot
        is_real = .false.
        i = 1
        if (len(s) == 0) return
        if (s(1:1) == '+' .or. s(1:1) == '-') i = 2
        mantissa_digits = 0
        seen_dot = .false.
        do while (i <= len(s))
            if (s(i:i) >= '0' .and. s(i:i) <= '9') then
                mantissa_digits = mantissa_digits + 1
            else if (s(i:i) == '.' .and. .not. seen_dot) then
                seen_dot = .true.
            else
                exit
            end if
            i = i + 1
        end do
        if (mantissa_digits == 0) return
        if (i > len(s)) then
            is_real = .true.
            return
        end if
        if (index('eEdD', s(i:i)) == 0) return
        i = i + 1
        if (i <= len(s)) then
            if (s(i:i) == '+' .or. s(i:i) == '-') i = i + 1
        end if
        exponent_digits = 0
        do while (i <= len(s))
            if (s(i:i) < '0' .or. s(i:i) > '9') return
            exponent_digits = exponent_digits + 1
            i = i + 1
        end do
        is_real = exponent_digits > 0
    end function is_real

    !> Power of ten of the leading nonzero digit of a number that `is_real` accepted
    !> ('20000' 4, '0.05' -2, '1e999' 999); -huge(1) for zero. The exponent is capped so
    !> that no digit string overflows the integer.
    pure integer function decimal_magnitude(s) result(magnitude)
        character(len=*), intent(in) :: s
        integer :: i, digits, integer_digits, leading, exponent
        logical :: seen_dot, negative
        digits = 0
        integer_digits = 0
        leading = 0
        seen_dot = .false.
        i = 1
        if (s(1:1) == '+' .or. s(1:1) == '-') i = 2
        do while (i <= len(s))
            if (s(i:i) == '.') then
                seen_dot = .true.
            else if (s(i:i) >= '0' .and. s(i:i) <= '9') then
                digits = digits + 1
                if (.not. seen_dot) integer_digits = integer_digits + 1
                if (leading == 0 .and. s(i:i) /= '0') leading = digits
            else
                exit
            end if
            i = i + 1
        end do
        if (leading == 0) then
            magnitude = -huge(1)
            return
        end if
        exponent = 0
        negative = .false.
        if (i < len(s)) then
            i = i + 1
            if (s(i:i) == '+' .or. s(i:i) == '-') then
                negative = s(i:i) == '-'
                i = i + 1
            end if
            do while (i <= len(s))
                exponent = min(10*exponent + (iachar(s(i:i)) - iachar('0')), 100000)
                i = i + 1
            end do
        end if
        if (negative) exponent = -exponent
        magnitude = integer_digits - leading + exponent
    end function decimal_magnitude

    pure function upper(s) result(u)
        character(len=*), intent(in) :: s
        character(len=len(s)) :: u
        integer :: i
        u = s
        do i = 1, len(s)
            if (s(i:i) >= 'a' .and. s(i:i) <= 'z') u(i:i) = achar(iachar(s(i:i)) - 32)
        end do
    end function upper

end module cfrd_cards
