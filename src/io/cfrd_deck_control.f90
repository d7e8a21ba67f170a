!> CONTROL: the card of numbers (counts, analysis type, PA, GAMMAW, solver), the EFFECTS
!> card and the ERRCTL card, read against the card schema; the effects applied once the
!> whole deck is read.
module cfrd_deck_control
    use cfrd_error, only: error_t
    use cfrd_model, only: model_t, effects_t
    use cfrd_effects, only: apply_effects
    use cfrd_cards, only: card_t, get_text, field_error, card_error, to_text
    use cfrd_card_schema, only: control_fields, effects_fields, errctl_fields
    use cfrd_card_reader, only: card_values_t, read_card
    use cfrd_deck_groups, only: group_cards_t, counts_t, leading_word, effects_keyword, &
                                errctl_keyword
    implicit none
    private

    public :: read_control, apply_deck_effects

contains

    subroutine read_control(file, group, model, counts, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(counts_t), intent(out) :: counts
        type(error_t), allocatable, intent(out) :: error
        type(card_values_t) :: v
        integer :: i, numbers, effects, errctl
        ! No data card means all defaults (a blank card cannot be written: blank lines are
        ! skipped). The EFFECTS and ERRCTL cards may come before or after the card of numbers.
        numbers = 0
        effects = 0
        errctl = 0
        do i = 1, group%n
            select case (leading_word(group%cards(i)))
            case (errctl_keyword)
                call take_once(errctl, errctl_keyword)
            case (effects_keyword)
                call take_once(effects, effects_keyword)
            case default
                if (numbers > 0) then
                    call card_error(error, file, group%cards(i), 'CONTROL takes one card '// &
                                    'of numbers and one EFFECTS card (the card of numbers '// &
                                    'is at line '//to_text(group%cards(numbers)%line)//')')
                    return
                end if
                numbers = i
            end select
            if (allocated(error)) return
        end do
        if (effects > 0) then
            call read_effects(file, group%cards(effects), model%effects, error)
            if (allocated(error)) return
        end if
        if (errctl > 0) then
            call read_card(file, group%cards(errctl), errctl_fields, 'CONTROL ERRCTL', v, &
                           error, only=[2, 3])
            if (allocated(error)) return
            model%error_tolerance = v%x(2)
            model%max_depth = v%int(3)
        end if
        if (numbers == 0) return
        associate (card => group%cards(numbers))
            counts%line = card%line
            ! The three counts are read before any is checked.
            call read_card(file, card, control_fields, 'CONTROL', v, error, only=[1, 2, 3], &
                           parse_first=.true.)
            if (allocated(error)) return
            call read_card(file, card, control_fields, 'CONTROL', v, error, &
                           only=[4, 5, 6, 7, 8, 9, 10, 11])
            if (allocated(error)) return
        end associate
        counts%nnode = v%int(1)
        counts%nelem = v%int(2)
        counts%nmat = v%int(3)
        model%analysis = v%int(4)
        model%pa = v%x(5)
        model%gamma_w = v%x(6)
        model%newtop = v%int(8)
        model%solver = v%int(9)
        model%tolerance = v%x(10)
        model%max_iterations = v%int(11)
    contains
        !> Card i is the keyword card `word`, of which CONTROL takes one: `first` its index.
        subroutine take_once(first, word)
            integer, intent(inout) :: first
            character(len=*), intent(in) :: word
            if (first > 0) then
                call card_error(error, file, group%cards(i), 'CONTROL takes one '//word// &
                                ' card (the first is at line '// &
                                to_text(group%cards(first)%line)//')')
                return
            end if
            first = i
        end subroutine take_once
    end subroutine read_control

    !> The EFFECTS card: each field a keyword, blank for the default (the effect on, the
    !> first word of the field's schema).
    subroutine read_effects(file, card, effects, error)
        character(len=*), intent(in) :: file
        type(card_t), intent(in) :: card
        type(effects_t), intent(out) :: effects
        type(error_t), allocatable, intent(out) :: error
        type(card_values_t) :: v
        effects%line = card%line
        call read_card(file, card, effects_fields, 'CONTROL EFFECTS', v, error, &
                       only=[2, 3, 4, 5, 6, 7, 8, 9])
        if (allocated(error)) return
        effects%nonlinear_rockfill = v%int(2) == 1
        effects%unload = v%int(3) == 1
        effects%water = v%int(4) == 1
        effects%interface = v%int(5) == 1
        effects%friction = v%int(6) == 1
        effects%large_slip = v%int(7) == 1
        effects%phases = v%int(8) == 1
        effects%creep = v%int(9) == 1
    end subroutine read_effects

    !> Apply the EFFECTS card to the model read (cfrd_effects); a request the model cannot
    !> meet is an error of the card's field.
    subroutine apply_deck_effects(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: message
        integer :: field, i
        if (model%effects%line == 0) return
        call apply_effects(model, field, message)
        if (field == 0) return
        do i = 1, group%n
            if (group%cards(i)%line /= model%effects%line) cycle
            call line_error_of(group%cards(i))
            return
        end do
    contains
        subroutine line_error_of(card)
            type(card_t), intent(in) :: card
            character(len=:), allocatable :: word
            call get_text(card, effects_fields, field + 1, word)
            call field_error(error, file, card, effects_fields, field + 1, 'CONTROL EFFECTS', &
                             'an effect this deck can switch ('//message//')', word)
        end subroutine line_error_of
    end subroutine apply_deck_effects
end module cfrd_deck_control
