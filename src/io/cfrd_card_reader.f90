!> The generic card reader: the fields of a card read and checked against its layout in the
!> card schema (cfrd_card_schema): syntax, blank fields and their defaults, limits and
!> accepted words, each failure the field error of the manual. Group readers read a card in
!> the order their messages need (`only`), with their cross-reference checks in between.
module cfrd_card_reader
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_cards, only: card_t, field_t, int_field, real_field, text_field, &
                          found_value, found_blank, found_upper, default_pa, get_int, &
                          get_real, get_text, field_error, upper, to_text
    implicit none
    private

    public :: card_values_t, read_card, raw_text, position, group_list

    type :: text_t
        character(len=:), allocatable :: s
    end type text_t

    !> The fields of one card as read: numbers (integers exactly; the position of the word
    !> in a text field with words), the texts of text fields (blanks trimmed), and whether
    !> each field was not blank.
    type :: card_values_t
        real(dp), allocatable :: x(:)
        logical, allocatable :: given(:)
        type(text_t), allocatable :: texts(:)
    contains
        procedure :: int => int_value
        procedure :: text => text_value
    end type card_values_t

contains

    !> Read the fields `only` (default: all, in column order) of `card` into `values`, each
    !> checked as its layout says right after it is read; with `parse_first`, all of them
    !> are read before any is checked. `pa` is the atmospheric pressure for defaults given
    !> as a fraction of it.
    subroutine read_card(file, card, fields, context, values, error, only, parse_first, pa)
        character(len=*), intent(in) :: file, context
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        type(card_values_t), intent(inout) :: values
        type(error_t), allocatable, intent(out) :: error
        integer, intent(in), optional :: only(:)
        logical, intent(in), optional :: parse_first
        real(dp), intent(in), optional :: pa
        integer, allocatable :: order(:)
        integer :: i, n
        logical :: together
        n = size(fields)
        if (allocated(values%x)) then
            if (size(values%x) /= n) deallocate (values%x, values%given, values%texts)
        end if
        if (.not. allocated(values%x)) allocate (values%x(n), values%given(n), values%texts(n))
        if (present(only)) then
            order = only
        else
            order = [(i, i=1, n)]
        end if
        together = .false.
        if (present(parse_first)) together = parse_first
        do i = 1, size(order)
            call read_field(order(i))
            if (allocated(error)) return
            if (.not. together) call check_field(file, card, fields, order(i), context, &
                                                 values, error)
            if (allocated(error)) return
        end do
        if (.not. together) return
        do i = 1, size(order)
            call check_field(file, card, fields, order(i), context, values, error)
            if (allocated(error)) return
        end do
    contains
        subroutine read_field(k)
            integer, intent(in) :: k
            real(dp) :: default
            integer :: value
            character(len=:), allocatable :: text
            default = fields(k)%default
            if (fields(k)%default_from > 0) then
                default = fields(k)%default_scale*values%x(fields(k)%default_from)
            else if (fields(k)%default_from == default_pa) then
                default = fields(k)%default_scale*pa
            end if
            select case (fields(k)%kind)
            case (int_field)
                call get_int(file, card, fields, k, context, nint(default), value, error, &
                             values%given(k))
                values%x(k) = real(value, dp)
            case (real_field)
                call get_real(file, card, fields, k, context, default, values%x(k), error, &
                              values%given(k))
            case default
                call get_text(card, fields, k, text)
                values%given(k) = len(text) > 0
                values%x(k) = 0.0_dp
                if (len_trim(fields(k)%words) > 0) then
                    values%x(k) = default
                    if (values%given(k)) values%x(k) = word_position(fields(k), text)
                end if
                values%texts(k)%s = text
            end select
        end subroutine read_field
    end subroutine read_card

    !> The checks of field k's layout on the value read.
    subroutine check_field(file, card, fields, k, context, values, error)
        character(len=*), intent(in) :: file, context
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        type(card_values_t), intent(in) :: values
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: x
        logical :: inside
        character(len=:), allocatable :: found
        associate (field => fields(k))
            if (len_trim(field%expected) == 0) return
            x = values%x(k)
            if (field%kind == text_field .and. len_trim(field%words) > 0) then
                inside = x > 0.0_dp
            else if (field%kind == text_field) then
                inside = .true.
            else
                inside = (x > field%lo .or. (x == field%lo .and. .not. field%lo_open)) .and. &
                         (x < field%hi .or. (x == field%hi .and. .not. field%hi_open))
            end if
            if (field%required .and. .not. values%given(k)) then
                found = ''
            else if (.not. inside) then
                select case (field%found)
                case (found_value)
                    found = to_text(nint(x))
                case (found_blank)
                    found = raw_text(card, fields, k)
                    if (len(found) == 0) found = '(blank)'
                case (found_upper)
                    found = upper(raw_text(card, fields, k))
                case default
                    found = raw_text(card, fields, k)
                end select
            else
                return
            end if
            call field_error(error, file, card, fields, k, context, trim(field%expected), found)
        end associate
    end subroutine check_field

    !> Position of a text among the words of a field (case ignored); 0 if absent or blank.
    pure real(dp) function word_position(field, text) result(p)
        type(field_t), intent(in) :: field
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: word
        integer :: n, start, finish
        p = 0.0_dp
        if (len(text) == 0) return
        word = upper(text)
        n = 0
        start = 1
        do while (start <= len_trim(field%words))
            if (field%words(start:start) == ' ') then
                start = start + 1
                cycle
            end if
            finish = index(field%words(start:)//' ', ' ') + start - 2
            n = n + 1
            if (field%words(start:finish) == word) then
                p = real(n, dp)
                return
            end if
            start = finish + 1
        end do
    end function word_position

    !> Field k as an integer.
    pure integer function int_value(self, k)
        class(card_values_t), intent(in) :: self
        integer, intent(in) :: k
        int_value = nint(self%x(k))
    end function int_value

    !> Text field k, blanks trimmed at both ends.
    function text_value(self, k) result(text)
        class(card_values_t), intent(in) :: self
        integer, intent(in) :: k
        character(len=:), allocatable :: text
        text = self%texts(k)%s
    end function text_value

    !> The text of field k (blanks trimmed), as quoted after "found".
    function raw_text(card, fields, k) result(text)
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        character(len=:), allocatable :: text
        call get_text(card, fields, k, text)
    end function raw_text

    !> Index of `word` in `names` (blank-padded comparison), 0 if absent. (gfortran 12's
    !> findloc compares character arrays of unequal length wrongly.)
    pure integer function position(names, word)
        character(len=*), intent(in) :: names(:), word
        integer :: i
        position = 0
        do i = 1, size(names)
            if (names(i) == word) then
                position = i
                return
            end if
        end do
    end function position

    !> The names of the element groups, for messages.
    function group_list(names) result(text)
        character(len=*), intent(in) :: names(:)
        character(len=:), allocatable :: text
        integer :: i
        if (size(names) == 0) then
            text = 'the deck names none'
            return
        end if
        text = trim(names(1))
        do i = 2, size(names)
            text = text//', '//trim(names(i))
        end do
    end function group_list
end module cfrd_card_reader
