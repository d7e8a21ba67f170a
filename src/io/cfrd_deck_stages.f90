!> STAGES: the construction and loading history, one card per stage, with the stage dates
!> read as day numbers that must go forwards. The fields are read and checked against the
!> card schema; here remain the keywords and the checks against groups, load sets and the
!> reservoir.
module cfrd_deck_stages
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, input_error
    use cfrd_model, only: model_t, stage_fill, stage_load, stage_reset, stage_water, &
                          stage_wait, stage_wet, has_creep, has_wetting, no_date
    use cfrd_cards, only: card_t, field_t, field_error, card_error, upper, to_text
    use cfrd_strings, only: level_text
    use cfrd_dates, only: parse_date, date_forms
    use cfrd_card_schema, only: stage_fields, load_stage_fields, water_stage_fields, &
                                wet_stage_fields
    use cfrd_card_reader, only: card_values_t, read_card, raw_text, position, group_list
    use cfrd_deck_groups, only: group_cards_t
    implicit none
    private

    public :: read_stages

    !> The dates of the stages read so far, to check that they go forwards.
    type :: date_reader_t
        real(dp) :: last_day = no_date
        character(len=:), allocatable :: last_text
        integer :: last_line = 0
    contains
        procedure :: read => read_stage_date
    end type date_reader_t

contains

    !> The STAGES group; without one, a single LOAD stage of the default load set.
    subroutine read_stages(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: keyword, name, date, label, ctx
        type(card_values_t) :: v
        integer :: i, k, g
        logical :: creeping
        logical, allocatable :: filled(:)
        type(date_reader_t) :: dates
        creeping = has_creep(model)
        if (.not. group%present) then
            allocate (model%stages(1))
            model%stages(1)%label = 'LOADS'
            model%stages(1)%date = ''
            return
        end if
        if (group%n == 0) then
            call fatal_error(error, file//':'//to_text(group%header_line)//': STAGES has '// &
                             'no stage cards', input_error)
            return
        end if
        allocate (model%stages(group%n), filled(size(model%mesh%group_name)))
        filled = .false.
        do i = 1, group%n
            associate (card => group%cards(i), stage => model%stages(i))
                stage%line = card%line
                keyword = upper(raw_text(card, stage_fields, 1))
                ctx = 'STAGES '//keyword
                date = raw_text(card, stage_fields, 4)
                label = raw_text(card, stage_fields, 5)
                ! A date in a date form gives the stage its time; free text is a label,
                ! except where time matters (a WAIT stage, a deck with CREEP cards).
                call dates%read(file, card, stage_fields, 4, ctx, date, &
                                keyword == 'WAIT' .or. creeping, stage%day, error)
                if (allocated(error)) return
                stage%date = date
                stage%label = keyword
                if (len(date) > 0) stage%label = stage%label//' '//date
                if (len(label) > 0) stage%label = stage%label//' '//label
                select case (keyword)
                case ('FILL')
                    stage%kind = stage_fill
                    name = raw_text(card, stage_fields, 2)
                    g = position(model%mesh%group_name, upper(name))
                    if (g == 0) then
                        call field_error(error, file, card, stage_fields, 2, ctx, &
                                         'an element group ('// &
                                         group_list(model%mesh%group_name)//')', name)
                        return
                    end if
                    if (filled(g)) then
                        call field_error(error, file, card, stage_fields, 2, ctx, &
                                         'a group not filled before', name)
                        return
                    end if
                    filled(g) = .true.
                    stage%group = g
                    stage%label = 'FILL '//trim(model%mesh%group_name(g))// &
                                  stage%label(5:)
                case ('LOAD')
                    stage%kind = stage_load
                    name = upper(raw_text(card, load_stage_fields, 2))
                    stage%load_set = 0
                    do k = 1, size(model%load_sets)
                        if (model%load_sets(k)%name == name) stage%load_set = k
                    end do
                    if (stage%load_set == 0) then
                        call field_error(error, file, card, load_stage_fields, 2, ctx, &
                                         'blank (the unnamed LOADS) or the name of a '// &
                                         'LOADS group', name)
                        return
                    end if
                    if (len(name) > 0) stage%label = 'LOAD '//name//stage%label(5:)
                case ('RESET')
                    stage%kind = stage_reset
                case ('WAIT')
                    stage%kind = stage_wait
                    if (len(date) == 0) then
                        call field_error(error, file, card, stage_fields, 4, ctx, &
                                         'the date to wait until (WAIT needs a date)', '')
                        return
                    end if
                case ('WATER')
                    stage%kind = stage_water
                    if (size(model%wet_faces) == 0) then
                        call card_error(error, file, card, 'WATER stage, but the deck has '// &
                                        'no RESERVOIR faces for the water to act on')
                        return
                    end if
                    call read_card(file, card, water_stage_fields, ctx, v, error, only=[2])
                    if (allocated(error)) return
                    stage%level = v%x(2)
                    stage%label = 'WATER '//level_text(stage%level)//stage%label(6:)
                case ('WET')
                    stage%kind = stage_wet
                    if (.not. has_wetting(model)) then
                        call card_error(error, file, card, 'WET stage, but no material '// &
                                        'has a WETTING card (nothing would collapse)')
                        return
                    end if
                    ! blank: every element; else those whose centroid lies below LEVEL
                    call read_card(file, card, wet_stage_fields, ctx, v, error, only=[2])
                    if (allocated(error)) return
                    stage%level = v%x(2)
                    if (v%given(2)) stage%label = 'WET '//level_text(stage%level)// &
                                                  stage%label(4:)
                case default
                    call card_error(error, file, card, "unknown stage '"//keyword// &
                                    "' in STAGES: expected FILL, LOAD, RESET, WATER, "// &
                                    "WAIT or WET")
                    return
                end select
                call read_card(file, card, stage_fields, ctx, v, error, only=[3])
                if (allocated(error)) return
                stage%increments = v%int(3)
            end associate
        end do
    end subroutine read_stages

    !> The date of a stage card (field k of `fields`, text `date`) as a day number in
    !> `day`: no_date when blank, or when free text is allowed (`required_form` false) and
    !> the text is no date. A date earlier than the last one read is an error.
    subroutine read_stage_date(self, file, card, fields, k, context, date, required_form, &
                               day, error)
        class(date_reader_t), intent(inout) :: self
        character(len=*), intent(in) :: file, context, date
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        logical, intent(in) :: required_form
        real(dp), intent(out) :: day
        type(error_t), allocatable, intent(out) :: error
        logical :: ok
        day = no_date
        if (len_trim(date) == 0) return
        call parse_date(date, day, ok)
        if (.not. ok) then
            day = no_date
            if (required_form) call field_error(error, file, card, fields, k, context, &
                                                date_forms, date)
            return
        end if
        if (day < self%last_day) then
            call field_error(error, file, card, fields, k, context, 'a date not before '// &
                             self%last_text//' (line '//to_text(self%last_line)// &
                             '): stages go forwards in time', date)
            return
        end if
        self%last_day = day
        self%last_text = trim(adjustl(date))
        self%last_line = card%line
    end subroutine read_stage_date
end module cfrd_deck_stages
