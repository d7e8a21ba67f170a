!> The card schema against the card manual: every layout of cfrd_card_schema must appear as
!> a field table of docs/cards.md (same fields in the same order, same columns, same name,
!> format of the same kind and width, and the same default and limits where the table has
!> those columns), and every field table of the manual must be the layout of some card, so
!> that the manual and the reader cannot drift apart. The reference is the manual itself,
!> parsed here from its markdown tables.
module test_io_card_schema
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, fail
    use cfrd_kinds, only: dp
    use cfrd_cards, only: field_t, int_field, real_field, text_field, default_pa, upper, &
                          to_text, is_real
    use cfrd_card_schema, only: card_schema_t, card_schemas
    implicit none
    private

    public :: collect_io_card_schema

    character(len=*), parameter :: manual = 'docs/cards.md'

    !> One row of a field table of the manual: its group section, card number (0 without a
    !> `card` column), columns, format and name cells, and the default and limits cells
    !> (the `values` column of a table of words; blank when the table has no such column).
    type :: doc_row_t
        integer :: table = 0
        character(len=:), allocatable :: group, columns, format, name, default, limits
        integer :: card = 0
    end type doc_row_t

    real(dp), parameter :: big = huge(1.0_dp)

    !> Fields (`layout:FIELD`) whose default cell says what the schema cannot: a count of
    !> CONTROL left blank is not checked (its value 0 means "not given"), and a blank L of
    !> ELEMENTS repeats K (a triangle), which the ELEMENTS reader does.
    character(len=*), parameter :: default_exceptions(4) = [character(len=24) :: &
        'CONTROL:NNODE', 'CONTROL:NELEM', 'CONTROL:NMAT', 'ELEMENTS:L']
    !> Fields whose limits in the schema differ from the manual's, on purpose: the counts
    !> of CONTROL take 0 for blank ("not given"; the manual, like the words of the message,
    !> gives the limits of a count that is given).
    character(len=*), parameter :: limits_exceptions(3) = [character(len=13) :: &
        'CONTROL:NNODE', 'CONTROL:NELEM', 'CONTROL:NMAT']

contains

    subroutine collect_io_card_schema(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('layouts_in_column_order', test_layouts_in_order), &
                new_unittest('every_layout_in_the_manual', test_layouts_documented), &
                new_unittest('every_manual_table_a_layout', test_tables_are_layouts), &
                new_unittest('defaults_and_limits_as_in_the_manual', &
                             test_defaults_and_limits) &
                ]
    end subroutine collect_io_card_schema

    !> Fields of a layout follow one another without overlap inside columns 1-90 (the
    !> EFFECTS card alone passes column 80), and every checked field says what it expects.
    subroutine test_layouts_in_order(error)
        type(error_t), allocatable, intent(out) :: error
        type(card_schema_t), allocatable :: cards(:)
        integer :: c, k
        cards = card_schemas()
        do c = 1, size(cards)
            associate (f => cards(c)%fields)
                do k = 1, size(f)
                    if (f(k)%first < 1 .or. f(k)%width < 1 .or. &
                        f(k)%first + f(k)%width - 1 > 90) then
                        call fail(error, cards(c)%name//' field '//trim(f(k)%name)// &
                                  ': columns outside 1-90')
                        return
                    end if
                    if (k > 1) then
                        if (f(k)%first < f(k - 1)%first + f(k - 1)%width) then
                            call fail(error, cards(c)%name//' field '//trim(f(k)%name)// &
                                      ' overlaps field '//trim(f(k - 1)%name))
                            return
                        end if
                    end if
                    if ((f(k)%required .or. len_trim(f(k)%words) > 0) .and. &
                        len_trim(f(k)%expected) == 0) then
                        call fail(error, cards(c)%name//' field '//trim(f(k)%name)// &
                                  ' is checked but has no "expected" words')
                        return
                    end if
                end do
            end associate
        end do
    end subroutine test_layouts_in_order

    !> Each layout of the schema is a table (or the rows of one card of a table) in its
    !> group's section of the manual.
    subroutine test_layouts_documented(error)
        type(error_t), allocatable, intent(out) :: error
        type(card_schema_t), allocatable :: cards(:)
        type(doc_row_t), allocatable :: rows(:)
        character(len=:), allocatable :: why
        integer :: c
        call read_manual(rows, error)
        if (allocated(error)) return
        cards = card_schemas()
        do c = 1, size(cards)
            if (.not. documented(cards(c), rows, why)) then
                call fail(error, cards(c)%name//' in '//manual//': '//why)
                return
            end if
        end do
    end subroutine test_layouts_documented

    !> Each field table of the manual (each card of a table with a `card` column) is the
    !> layout of a card of the schema.
    subroutine test_tables_are_layouts(error)
        type(error_t), allocatable, intent(out) :: error
        type(card_schema_t), allocatable :: cards(:)
        type(doc_row_t), allocatable :: rows(:)
        character(len=:), allocatable :: why
        integer :: r, c
        logical :: matched
        call read_manual(rows, error)
        if (allocated(error)) return
        cards = card_schemas()
        do r = 1, size(rows)
            if (r > 1) then
                if (rows(r)%table == rows(r - 1)%table .and. &
                    rows(r)%card == rows(r - 1)%card) cycle
            end if
            matched = .false.
            do c = 1, size(cards)
                if (cards(c)%group /= rows(r)%group .or. cards(c)%card /= rows(r)%card) cycle
                matched = table_matches(cards(c), rows, rows(r)%table, why)
                if (matched) exit
            end do
            if (.not. matched) then
                call fail(error, manual//': the table of '//rows(r)%group//' with field '// &
                          rows(r)%name//' (columns '//rows(r)%columns//') is the layout '// &
                          'of no card in cfrd_card_schema')
                return
            end if
        end do
    end subroutine test_tables_are_layouts

    !> The default and the limits of each field, where its table has those columns, are
    !> the schema's: 'required' for a field that must not be blank, the default's number,
    !> word or field ('N1', '2 K', '0.1 PA'), the bounds ('> 0', '0 <= NU < 0.5', '1..4',
    !> '0, 1', 'magnitude <= 1e7') and the words. Parentheses in a cell are comments;
    !> a cell of words about other cards ('existing node', 'N1 .. NNODE') is the group
    !> reader's check, not the schema's, and is left out, as are the fields listed above.
    !> The words of each field's "expected ..." message state what the schema checks and
    !> the manual says (`wording_matches`): a message never calls a rejected value allowed.
    subroutine test_defaults_and_limits(error)
        type(error_t), allocatable, intent(out) :: error
        type(card_schema_t), allocatable :: cards(:)
        type(doc_row_t), allocatable :: rows(:)
        character(len=:), allocatable :: why, key
        integer :: c, r, t, k
        call read_manual(rows, error)
        if (allocated(error)) return
        cards = card_schemas()
        do c = 1, size(cards)
            t = 0
            do r = 1, size(rows)
                if (rows(r)%group /= cards(c)%group) cycle
                if (table_matches(cards(c), rows, rows(r)%table, why)) then
                    t = rows(r)%table
                    exit
                end if
            end do
            if (t == 0) then
                call fail(error, cards(c)%name//': no table in '//manual)
                return
            end if
            k = 0
            do r = 1, size(rows)
                if (rows(r)%table /= t .or. rows(r)%card /= cards(c)%card) cycle
                k = k + 1
                key = cards(c)%name//':'//trim(cards(c)%fields(k)%name)
                if (.not. any(default_exceptions == key)) then
                    if (.not. default_matches(cards(c)%fields, k, rows(r)%default, why)) then
                        call fail(error, key//' default: '//why)
                        return
                    end if
                end if
                if (.not. any(limits_exceptions == key)) then
                    if (.not. limits_match(cards(c)%fields(k), rows(r)%limits, why)) then
                        call fail(error, key//' limits: '//why)
                        return
                    end if
                    if (.not. wording_matches(cards(c)%fields(k), rows(r)%limits, why)) then
                        call fail(error, key//' "expected" words: '//why)
                        return
                    end if
                end if
            end do
        end do
    end subroutine test_defaults_and_limits

    !> The default cell of field k: 'required', a number, a word of the field, or a field
    !> with its factor ('2 K', '0.1 PA'). A blank field whose value fails the field's own
    !> check is required; so may be a field the schema leaves to its group reader.
    logical function default_matches(fields, k, doc_cell, why) result(ok)
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        character(len=*), intent(in) :: doc_cell
        character(len=:), allocatable, intent(out) :: why
        character(len=:), allocatable :: cell, want, name
        character(len=:), allocatable :: words(:)
        real(dp) :: x, scale
        ok = .true.
        cell = plain(doc_cell)
        if (len(cell) == 0) return
        ! a condition on other fields, checked by the group reader
        if (index(cell, 'required if ') == 1) return
        associate (f => fields(k))
            if (f%required) then
                want = 'required'
            else if (f%default_from /= 0) then
                if (f%default_from > 0) then
                    name = trim(fields(f%default_from)%name)
                else if (f%default_from == default_pa) then
                    name = 'PA'
                end if
                want = name
                if (f%default_scale /= 1.0_dp) want = real_text(f%default_scale)//' '//name
                words = tokens(cell)
                scale = 1.0_dp
                if (size(words) == 2) then
                    if (is_real(trim(words(1)))) read (words(1), *) scale
                end if
                if (trim(words(size(words))) == name .and. scale == f%default_scale .and. &
                    size(words) <= 2) return
            else if (f%kind == text_field .and. len_trim(f%words) > 0) then
                want = 'required'
                if (f%default > 0.0_dp) then
                    words = tokens(f%words)
                    want = trim(words(nint(f%default)))
                end if
            else if (f%kind == text_field) then
                return   ! a text without words: its blank meaning is the reader's
            else if (len_trim(f%expected) > 0 .and. .not. inside(f, f%default)) then
                want = 'required'
            else
                want = real_text(f%default)
                if (cell == 'required' .and. len_trim(f%expected) == 0) return
                if (is_real(cell)) then
                    read (cell, *) x
                    if (x == f%default) return
                end if
            end if
            if (cell == want) return
            ok = .false.
            why = 'the manual says '''//cell//''', the schema '''//want//''''
        end associate
    end function default_matches

    !> The limits cell of a field the schema checks: its words, or its bounds.
    logical function limits_match(field, doc_cell, why) result(ok)
        type(field_t), intent(in) :: field
        character(len=*), intent(in) :: doc_cell
        character(len=:), allocatable, intent(out) :: why
        character(len=:), allocatable :: cell, want, got
        real(dp) :: lo, hi, schema_lo
        logical :: lo_open, hi_open, schema_lo_open, read_ok
        ok = .true.
        cell = plain(doc_cell)
        if (len(cell) == 0 .or. len_trim(field%expected) == 0) return
        if (field%kind == text_field) then
            if (len_trim(field%words) == 0) return
            want = joined(tokens(field%words))
            got = joined(tokens(list_of(cell)))
            if (got == want) return
            ok = .false.
            why = 'the manual gives the words '//got//', the schema '//want
            return
        end if
        call read_bounds(cell, lo, lo_open, hi, hi_open, read_ok)
        if (.not. read_ok) then
            ok = .false.
            why = 'the manual''s limits '''//cell//''' cannot be read as bounds'
            return
        end if
        ! the smallest positive real, closed, is "> 0"
        schema_lo = field%lo
        schema_lo_open = field%lo_open
        if (schema_lo == tiny(1.0_dp) .and. .not. schema_lo_open) then
            schema_lo = 0.0_dp
            schema_lo_open = .true.
        end if
        ok = lo == schema_lo .and. hi == field%hi .and. &
             ((lo_open .eqv. schema_lo_open) .or. lo == -big) .and. &
             ((hi_open .eqv. field%hi_open) .or. hi == big)
        if (ok) return
        why = 'the manual says '''//cell//''' ('//bounds_text(lo, lo_open, hi, hi_open)// &
              '), the schema '//bounds_text(schema_lo, schema_lo_open, field%hi, field%hi_open)
    end function limits_match

    !> The words of a field's "expected ..." message against the schema's check and the
    !> manual's limits cell: a field of words names the same words ('ON (the default, also
    !> blank) or OFF': ON OFF); a number states the same bounds ('a real with 0 <= N <=
    !> 0.999', 'a face from 1 to 4', '1 (plane strain) or 2 (axisymmetric)', 'magnitude at
    !> most 1e7'), or none where the schema has none ('the reservoir level to reach (m)').
    logical function wording_matches(field, doc_cell, why) result(ok)
        type(field_t), intent(in) :: field
        character(len=*), intent(in) :: doc_cell
        character(len=:), allocatable, intent(out) :: why
        character(len=:), allocatable :: stated, cell, message
        real(dp) :: lo, hi, schema_lo, doc_lo, doc_hi
        logical :: lo_open, hi_open, schema_lo_open, doc_lo_open, doc_hi_open, read_ok
        ok = .true.
        if (len_trim(field%expected) == 0) return
        message = 'the message "expected '//trim(field%expected)//'"'
        stated = stated_words(field%expected, trim(field%name), field%kind == text_field)
        if (field%kind == text_field) then
            if (len_trim(field%words) == 0) return
            ok = stated == joined(tokens(field%words))
            if (.not. ok) why = message//' names '//stated//', the schema checks '// &
                                joined(tokens(field%words))
            return
        end if
        schema_lo = field%lo
        schema_lo_open = field%lo_open
        if (schema_lo == tiny(1.0_dp) .and. .not. schema_lo_open) then
            schema_lo = 0.0_dp
            schema_lo_open = .true.
        end if
        if (len(stated) == 0) then
            ok = schema_lo == -big .and. field%hi == big
            if (.not. ok) why = message//' states no bounds, the schema checks '// &
                                bounds_text(schema_lo, schema_lo_open, field%hi, field%hi_open)
            return
        end if
        call read_bounds(stated, lo, lo_open, hi, hi_open, read_ok)
        ok = read_ok .and. lo == schema_lo .and. hi == field%hi .and. &
             ((lo_open .eqv. schema_lo_open) .or. lo == -big) .and. &
             ((hi_open .eqv. field%hi_open) .or. hi == big)
        if (.not. ok) then
            why = message//' states '''//stated//''', the schema checks '// &
                  bounds_text(schema_lo, schema_lo_open, field%hi, field%hi_open)
            return
        end if
        cell = plain(doc_cell)
        if (len(cell) == 0) return
        call read_bounds(cell, doc_lo, doc_lo_open, doc_hi, doc_hi_open, read_ok)
        if (.not. read_ok) return      ! words about other cards: the group reader's check
        ok = lo == doc_lo .and. hi == doc_hi .and. ((lo_open .eqv. doc_lo_open) .or. &
             lo == -big) .and. ((hi_open .eqv. doc_hi_open) .or. hi == big)
        if (.not. ok) why = message//' states '//bounds_text(lo, lo_open, hi, hi_open)// &
                            ', the manual '''//cell//''''
    end function wording_matches

    !> What a message states, as a limits cell: its comments in parentheses left out, 'at
    !> most' read as '<=' and 'from a to b' as 'a..b', and of the rest only the numbers,
    !> the comparisons, 'magnitude' and the field's name (of a field of words: its words
    !> in capitals).
    function stated_words(expected, name, capitals) result(text)
        character(len=*), intent(in) :: expected, name
        logical, intent(in) :: capitals
        character(len=:), allocatable :: text, bare, w
        character(len=:), allocatable :: words(:)
        integer :: i, depth
        bare = ''
        depth = 0
        do i = 1, len_trim(expected)
            if (expected(i:i) == '(') depth = depth + 1
            if (depth == 0) then
                if (index(',:', expected(i:i)) > 0) then
                    bare = bare//' '
                else
                    bare = bare//expected(i:i)
                end if
            end if
            if (expected(i:i) == ')') depth = max(depth - 1, 0)
        end do
        words = tokens(bare)
        text = ''
        i = 0
        do while (i < size(words))
            i = i + 1
            w = trim(words(i))
            if (capitals) then
                if (scan(w, 'ABCDEFGHIJKLMNOPQRSTUVWXYZ') > 0 .and. &
                    verify(w, 'ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-') == 0) text = text//' '//w
            else if (w == 'at' .and. i < size(words)) then
                if (trim(words(i + 1)) == 'most') then
                    text = text//' <='
                    i = i + 1
                end if
            else if (w == 'from' .and. i + 3 <= size(words)) then
                if (trim(words(i + 2)) == 'to') then
                    text = text//' '//trim(words(i + 1))//'..'//trim(words(i + 3))
                    i = i + 3
                end if
            else if (is_real(w) .or. w == '<' .or. w == '<=' .or. w == '>' .or. w == '>=' &
                     .or. w == 'magnitude' .or. w == name) then
                text = text//' '//w
            end if
        end do
        text = trim(adjustl(text))
    end function stated_words

    !> Bounds from '> a', '>= a', '< b', '<= b', 'a < X <= b' (any of < and <=), 'a..b',
    !> 'a, b, c' or 'a or b' (consecutive integers), 'magnitude <= m'.
    subroutine read_bounds(cell, lo, lo_open, hi, hi_open, ok)
        character(len=*), intent(in) :: cell
        real(dp), intent(out) :: lo, hi
        logical, intent(out) :: lo_open, hi_open, ok
        character(len=:), allocatable :: words(:)
        real(dp), allocatable :: x(:)
        integer :: i, dots
        lo = -big
        hi = big
        lo_open = .false.
        hi_open = .false.
        ok = .false.
        dots = index(cell, '..')
        if (dots > 0) then
            words = [character(len=len(cell)) :: cell(1:dots - 1), cell(dots + 2:)]
        else
            words = tokens(cell)
        end if
        if (size(words) == 2 .and. dots == 0 .and. any(trim(words(1)) == ['> ', '>=', '< ', &
                                                                          '<='])) then
            if (.not. is_real(trim(words(2)))) return
            select case (trim(words(1)))
            case ('>')
                read (words(2), *) lo
                lo_open = .true.
            case ('>=')
                read (words(2), *) lo
            case ('<')
                read (words(2), *) hi
                hi_open = .true.
            case default
                read (words(2), *) hi
            end select
            ok = .true.
        else if (size(words) == 3 .and. trim(words(1)) == 'magnitude' .and. &
                 trim(words(2)) == '<=') then
            if (.not. is_real(trim(words(3)))) return
            read (words(3), *) hi
            lo = -hi
            ok = .true.
        else if (size(words) == 5) then
            if (.not. (is_real(trim(words(1))) .and. is_real(trim(words(5))))) return
            if (.not. (any(trim(words(2)) == ['< ', '<=']) .and. &
                       any(trim(words(4)) == ['< ', '<=']))) return
            read (words(1), *) lo
            read (words(5), *) hi
            lo_open = trim(words(2)) == '<'
            hi_open = trim(words(4)) == '<'
            ok = .true.
        else
            if (dots == 0) words = tokens(list_of(cell))
            if (size(words) < 2) return
            if (.not. all([(is_real(trim(words(i))), i=1, size(words))])) return
            allocate (x(size(words)))
            do i = 1, size(words)
                read (words(i), *) x(i)
            end do
            if (dots == 0) then
                if (any(x(2:) - x(:size(x) - 1) /= 1.0_dp)) return
            end if
            lo = x(1)
            hi = x(size(x))
            ok = .true.
        end if
    end subroutine read_bounds

    !> A cell without backquotes, comments in parentheses and what follows ', ' and a
    !> word ('>= 1, divides N2 - N1': a check on other fields).
    function plain(cell) result(text)
        character(len=*), intent(in) :: cell
        character(len=:), allocatable :: text
        integer :: i, depth
        text = ''
        depth = 0
        do i = 1, len_trim(cell)
            if (cell(i:i) == '(') depth = depth + 1
            if (depth == 0 .and. cell(i:i) /= '`') text = text//cell(i:i)
            if (cell(i:i) == ')') depth = max(depth - 1, 0)
        end do
        do i = 1, len(text) - 2
            if (text(i:i + 1) == ', ' .and. index('abcdefghijklmnopqrstuvwxyz', &
                                                  text(i + 2:i + 2)) > 0) then
                text = text(1:i - 1)
                exit
            end if
        end do
        text = trim(adjustl(text))
    end function plain

    !> A list 'a, b or c' as words separated by blanks.
    function list_of(cell) result(text)
        character(len=*), intent(in) :: cell
        character(len=:), allocatable :: text
        integer :: i
        text = ' '//cell//' '
        do i = 1, len(text)
            if (text(i:i) == ',') text(i:i) = ' '
        end do
        i = index(text, ' or ')
        do while (i > 0)
            text = text(1:i)//text(i + 4:)
            i = index(text, ' or ')
        end do
    end function list_of

    !> The blank-separated words of a text.
    function tokens(text) result(words)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: words(:)
        integer :: i, start
        allocate (character(len=max(len(text), 1)) :: words(0))
        i = 1
        do while (i <= len(text))
            if (text(i:i) == ' ') then
                i = i + 1
                cycle
            end if
            start = i
            do while (i <= len(text))
                if (text(i:i) == ' ') exit
                i = i + 1
            end do
            words = [character(len=max(len(text), 1)) :: words, text(start:i - 1)]
        end do
    end function tokens

    function joined(words) result(text)
        character(len=*), intent(in) :: words(:)
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        do i = 1, size(words)
            text = text//trim(words(i))
            if (i < size(words)) text = text//' '
        end do
    end function joined

    !> The value passes the field's bounds.
    pure logical function inside(field, x)
        type(field_t), intent(in) :: field
        real(dp), intent(in) :: x
        inside = (x > field%lo .or. (x == field%lo .and. .not. field%lo_open)) .and. &
                 (x < field%hi .or. (x == field%hi .and. .not. field%hi_open))
    end function inside

    function real_text(x) result(text)
        real(dp), intent(in) :: x
        character(len=:), allocatable :: text
        character(len=32) :: buffer
        if (abs(x) < 1.0e9_dp .and. x == aint(x)) then
            text = to_text(nint(x))
            return
        end if
        write (buffer, '(es12.5)') x
        text = trim(adjustl(buffer))
    end function real_text

    function bounds_text(lo, lo_open, hi, hi_open) result(text)
        real(dp), intent(in) :: lo, hi
        logical, intent(in) :: lo_open, hi_open
        character(len=:), allocatable :: text
        text = 'x'
        if (lo > -big) text = real_text(lo)//trim(merge(' < ', ' <=', lo_open))//' '//text
        if (hi < big) text = text//trim(merge(' < ', ' <=', hi_open))//' '//real_text(hi)
    end function bounds_text

    !> The card's layout is some table of its group; `why` tells the closest miss (the
    !> table with the most fields matched).
    logical function documented(card, rows, why)
        type(card_schema_t), intent(in) :: card
        type(doc_row_t), intent(in) :: rows(:)
        character(len=:), allocatable, intent(out) :: why
        character(len=:), allocatable :: miss
        integer :: r, matched, best
        documented = .false.
        best = -1
        why = 'no field table in section '//card%group
        do r = 1, size(rows)
            if (rows(r)%group /= card%group) cycle
            if (r > 1) then
                if (rows(r)%table == rows(r - 1)%table) cycle
            end if
            if (table_matches(card, rows, rows(r)%table, miss, matched)) then
                documented = .true.
                return
            end if
            if (matched > best) why = miss
            best = max(best, matched)
        end do
    end function documented

    !> The rows of table t (of the card's number) are the card's fields, in order.
    logical function table_matches(card, rows, t, why, matched)
        type(card_schema_t), intent(in) :: card
        type(doc_row_t), intent(in) :: rows(:)
        integer, intent(in) :: t
        character(len=:), allocatable, intent(out) :: why
        integer, intent(out), optional :: matched   !! fields matched before the first miss
        integer :: r, k
        table_matches = .false.
        if (present(matched)) matched = 0
        k = 0
        do r = 1, size(rows)
            if (rows(r)%table /= t .or. rows(r)%card /= card%card) cycle
            k = k + 1
            if (k > size(card%fields)) then
                why = 'the table has a field '//rows(r)%name//' that the card lacks'
                return
            end if
            if (.not. row_matches(card%fields(k), rows(r), why)) return
            if (present(matched)) matched = k
        end do
        if (k < size(card%fields)) then
            why = 'the table lacks field '//trim(card%fields(k + 1)%name)
            return
        end if
        table_matches = k > 0
        if (k == 0) why = 'an empty table'
    end function table_matches

    !> Columns `first-last`, the name (a keyword in backquotes stands for KEYWORD; `A / B`
    !> lists alternatives) and the format (I, F or A with the field's width).
    logical function row_matches(field, row, why)
        type(field_t), intent(in) :: field
        type(doc_row_t), intent(in) :: row
        character(len=:), allocatable, intent(out) :: why
        character(len=:), allocatable :: columns, name, letter
        row_matches = .false.
        columns = to_text(field%first)//'-'//to_text(field%first + field%width - 1)
        if (row%columns /= columns) then
            why = 'field '//trim(field%name)//' in columns '//columns//', the manual says '// &
                  row%columns//' ('//row%name//')'
            return
        end if
        name = row%name
        if (len(name) > 2) then
            if (name(1:1) == '`' .and. name(len(name):len(name)) == '`') name = 'KEYWORD'
        end if
        if (.not. among(trim(field%name), upper(name))) then
            why = 'field in columns '//columns//' is '//trim(field%name)// &
                  ', the manual says '//row%name
            return
        end if
        select case (field%kind)
        case (int_field)
            letter = 'I'
        case (real_field)
            letter = 'F'
        case default
            letter = 'A'
        end select
        if (.not. format_among(letter//to_text(field%width), row%format)) then
            why = 'field '//trim(field%name)//' has format '//letter//to_text(field%width)// &
                  ', the manual says '//row%format
            return
        end if
        row_matches = .true.
    end function row_matches

    !> `word` is one of the alternatives of `cell` ('GROUP / SET / LEVEL').
    logical function among(word, cell)
        character(len=*), intent(in) :: word, cell
        character(len=:), allocatable :: rest
        integer :: slash
        among = .false.
        rest = cell
        do
            slash = index(rest, '/')
            if (slash == 0) then
                among = trim(adjustl(rest)) == word
                return
            end if
            if (trim(adjustl(rest(1:slash - 1))) == word) then
                among = .true.
                return
            end if
            rest = rest(slash + 1:)
        end do
    end function among

    !> Format `want` ('F10') is one of the formats of `cell` ('A10 / F10', 'F10.0').
    logical function format_among(want, cell)
        character(len=*), intent(in) :: want, cell
        character(len=:), allocatable :: rest, one
        integer :: slash, dot
        format_among = .false.
        rest = cell//'/'
        do while (len(rest) > 0)
            slash = index(rest, '/')
            one = trim(adjustl(rest(1:slash - 1)))
            rest = rest(slash + 1:)
            dot = index(one, '.')
            if (dot > 0) one = one(1:dot - 1)
            if (one == want) then
                format_among = .true.
                return
            end if
        end do
    end function format_among

    !> The rows of every field table of the manual: a markdown table whose header has the
    !> cells `columns` and `name`, under a `### GROUP` heading.
    subroutine read_manual(rows, error)
        type(doc_row_t), allocatable, intent(out) :: rows(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: lines(:), cells(:)
        character(len=:), allocatable :: group
        integer :: i, ntable, c_columns, c_format, c_name, c_card, c_default, c_limits
        type(doc_row_t) :: row
        call read_lines(manual, lines, error)
        if (allocated(error)) return
        allocate (rows(0))
        group = ''
        ntable = 0
        i = 1
        do while (i <= size(lines))
            if (lines(i)(1:4) == '### ') then
                group = trim(lines(i)(5:))
                if (index(group, ' ') > 0) group = group(1:index(group, ' ') - 1)
            end if
            if (is_table_header(i)) then
                call split_cells(lines(i), cells)
                c_columns = cell_index(cells, 'columns')
                c_format = cell_index(cells, 'format')
                c_name = cell_index(cells, 'name')
                c_card = cell_index(cells, 'card')
                c_default = cell_index(cells, 'default')
                c_limits = cell_index(cells, 'limits')
                if (c_limits == 0) c_limits = cell_index(cells, 'values')
                i = i + 2
                if (c_columns == 0 .or. c_name == 0 .or. c_format == 0) cycle
                ntable = ntable + 1
                do while (i <= size(lines))
                    if (lines(i)(1:1) /= '|') exit
                    call split_cells(lines(i), cells)
                    row%table = ntable
                    row%group = group
                    row%columns = trim(cells(c_columns))
                    row%format = trim(cells(c_format))
                    row%name = trim(cells(c_name))
                    row%default = ''
                    if (c_default > 0) row%default = trim(cells(c_default))
                    row%limits = ''
                    if (c_limits > 0) row%limits = trim(cells(c_limits))
                    row%card = 0
                    if (c_card > 0) read (cells(c_card), *) row%card
                    rows = [rows, row]
                    i = i + 1
                end do
                cycle
            end if
            i = i + 1
        end do
        if (size(rows) == 0) call fail(error, manual//': no field tables found')
    contains
        !> Line j is a table header: a table line followed by the `|---` line.
        logical function is_table_header(j)
            integer, intent(in) :: j
            is_table_header = .false.
            if (j >= size(lines)) return
            is_table_header = lines(j)(1:1) == '|' .and. lines(j + 1)(1:4) == '|---'
        end function is_table_header
    end subroutine read_manual

    !> The cells of a table line, blanks trimmed ('\|' inside a cell is not a separator).
    subroutine split_cells(line, cells)
        character(len=*), intent(in) :: line
        character(len=:), allocatable, intent(out) :: cells(:)
        character(len=len(line)) :: cell
        integer :: i, k
        allocate (character(len=len(line)) :: cells(0))
        k = 0
        cell = ''
        do i = 2, len_trim(line)
            if (line(i:i) == '|' .and. line(i - 1:i - 1) /= '\') then
                cells = [character(len=len(line)) :: cells, adjustl(cell)]
                cell = ''
                k = 0
            else
                k = k + 1
                cell(k:k) = line(i:i)
            end if
        end do
    end subroutine split_cells

    integer function cell_index(cells, word)
        character(len=*), intent(in) :: cells(:), word
        integer :: i
        cell_index = 0
        do i = 1, size(cells)
            if (trim(cells(i)) == word) then
                cell_index = i
                return
            end if
        end do
    end function cell_index

    !> The lines of a text file, each padded to the longest.
    subroutine read_lines(path, lines, error)
        character(len=*), intent(in) :: path
        character(len=:), allocatable, intent(out) :: lines(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=4096) :: buffer
        integer :: unit, stat, n, longest
        open (newunit=unit, file=path, status='old', action='read', iostat=stat)
        if (stat /= 0) then
            call fail(error, path//': cannot open (run the tests from the repository root)')
            return
        end if
        n = 0
        longest = 4
        do
            read (unit, '(a)', iostat=stat) buffer
            if (stat /= 0) exit
            n = n + 1
            longest = max(longest, len_trim(buffer))
        end do
        rewind (unit)
        allocate (character(len=longest) :: lines(n))
        do n = 1, size(lines)
            read (unit, '(a)') buffer
            lines(n) = buffer
        end do
        close (unit)
    end subroutine read_lines
end module test_io_card_schema
