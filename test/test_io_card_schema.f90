!> The card schema against the card manual: every layout of cfrd_card_schema must appear as
!> a field table of docs/cards.md (same fields in the same order, same columns, same name,
!> format of the same kind and width), and every field table of the manual must be the
!> layout of some card, so that the manual and the reader cannot drift apart. The reference
!> is the manual itself, parsed here from its markdown tables.
module test_io_card_schema
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, fail
    use cfrd_cards, only: field_t, int_field, real_field, text_field, upper, to_text
    use cfrd_card_schema, only: card_schema_t, card_schemas
    implicit none
    private

    public :: collect_io_card_schema

    character(len=*), parameter :: manual = 'docs/cards.md'

    !> One row of a field table of the manual: its group section, card number (0 without a
    !> `card` column), columns, format and name cells.
    type :: doc_row_t
        integer :: table = 0
        character(len=:), allocatable :: group, columns, format, name
        integer :: card = 0
    end type doc_row_t

contains

    subroutine collect_io_card_schema(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('layouts_in_column_order', test_layouts_in_order), &
                new_unittest('every_layout_in_the_manual', test_layouts_documented), &
                new_unittest('every_manual_table_a_layout', test_tables_are_layouts) &
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
    !> layout of a card of the schema. TITLE's table is left out: it documents the header
    !> card itself, whose title the group sorter reads, not a data card.
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
            if (rows(r)%group == 'TITLE') cycle
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
        integer :: i, ntable, c_columns, c_format, c_name, c_card
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
