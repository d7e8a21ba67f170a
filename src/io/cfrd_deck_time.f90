!> The cards of the rockfill's delayed deformation (docs/cards.md): the CREEP and WETTING
!> cards that may follow an EB material's two parameter cards, and the stage dates read as day numbers (checked to
!> go forwards). Every problem is a field error naming file, line, columns and field.
module cfrd_deck_time
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_model, only: material_t, no_date
    use cfrd_cards, only: card_t, field_t, real_field, text_field, get_real, get_text, &
                          field_error, upper, to_text
    use cfrd_dates, only: parse_date, date_forms
    implicit none
    private

    public :: is_creep_card, read_creep_card, date_reader_t
    public :: is_wetting_card, read_wetting_card

    type(field_t), parameter :: creep_fields(6) = [ &
                                field_t('KEYWORD', 1, 10, text_field), &
                                field_t('ALPHA', 11, 10, real_field), &
                                field_t('B', 21, 10, real_field), &
                                field_t('MC', 31, 10, real_field), &
                                field_t('D', 41, 10, real_field), &
                                field_t('L', 51, 10, real_field)]

    type(field_t), parameter :: wetting_fields(4) = [ &
                                  field_t('KEYWORD', 1, 10, text_field), &
                                  field_t('CW', 11, 10, real_field), &
                                  field_t('NW', 21, 10, real_field), &
                                  field_t('DW', 31, 10, real_field)]

    !> Bounds of the creep parameters: values beyond them are mistyped fields (published
    !> laboratory and back-analysed values lie well inside, docs/theory.md section 15).
    real(dp), parameter :: alpha_max = 1.0_dp     !! 1/day: 63 % of the creep in one day
    real(dp), parameter :: strain_max = 0.05_dp   !! final creep strains at pa, S/(1-S) = 1
    real(dp), parameter :: exponent_max = 3.0_dp

    !> The dates of the stages read so far, to check that they go forwards.
    type :: date_reader_t
        real(dp) :: last_day = no_date
        character(len=:), allocatable :: last_text
        integer :: last_line = 0
    contains
        procedure :: read => read_stage_date
    end type date_reader_t

contains

    !> A card whose columns 1-10 hold the keyword CREEP.
    logical function is_creep_card(card)
        type(card_t), intent(in) :: card
        character(len=:), allocatable :: keyword
        call get_text(card, creep_fields, 1, keyword)
        is_creep_card = upper(keyword) == 'CREEP'
    end function is_creep_card

    !> The CREEP card of EB material m: ALPHA (1/day), B, MC, D, L, each required.
    subroutine read_creep_card(file, card, m, mat, error)
        character(len=*), intent(in) :: file
        type(card_t), intent(in) :: card
        integer, intent(in) :: m
        type(material_t), intent(inout) :: mat
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: ctx
        ctx = 'MATERIALS '//to_text(m)//' CREEP'
        call bounded(file, card, creep_fields, 2, ctx, .false., alpha_max, &
                     'a real with 0 < ALPHA <= 1 (1/day)', mat%creep_alpha, error)
        if (allocated(error)) return
        call bounded(file, card, creep_fields, 3, ctx, .true., strain_max, &
                     'a real with 0 <= B <= 0.05', mat%creep_b, error)
        if (allocated(error)) return
        call bounded(file, card, creep_fields, 4, ctx, .false., exponent_max, &
                     'a real with 0 < MC <= 3', mat%creep_mc, error)
        if (allocated(error)) return
        call bounded(file, card, creep_fields, 5, ctx, .true., strain_max, &
                     'a real with 0 <= D <= 0.05', mat%creep_d, error)
        if (allocated(error)) return
        call bounded(file, card, creep_fields, 6, ctx, .false., exponent_max, &
                     'a real with 0 < L <= 3', mat%creep_l, error)
        if (allocated(error)) return
        mat%creep = .true.
    end subroutine read_creep_card

    !> A card whose columns 1-10 hold the keyword WETTING.
    logical function is_wetting_card(card)
        type(card_t), intent(in) :: card
        character(len=:), allocatable :: keyword
        call get_text(card, wetting_fields, 1, keyword)
        is_wetting_card = upper(keyword) == 'WETTING'
    end function is_wetting_card

    !> The WETTING card of EB material m: CW, NW, DW, each required (docs/theory.md s. 16).
    subroutine read_wetting_card(file, card, m, mat, error)
        character(len=*), intent(in) :: file
        type(card_t), intent(in) :: card
        integer, intent(in) :: m
        type(material_t), intent(inout) :: mat
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: ctx
        ctx = 'MATERIALS '//to_text(m)//' WETTING'
        call bounded(file, card, wetting_fields, 2, ctx, .true., strain_max, &
                     'a real with 0 <= CW <= 0.05', mat%wet_c, error)
        if (allocated(error)) return
        call bounded(file, card, wetting_fields, 3, ctx, .false., exponent_max, &
                     'a real with 0 < NW <= 3', mat%wet_n, error)
        if (allocated(error)) return
        call bounded(file, card, wetting_fields, 4, ctx, .true., strain_max, &
                     'a real with 0 <= DW <= 0.05', mat%wet_d, error)
        if (allocated(error)) return
        mat%wetting = .true.
    end subroutine read_wetting_card

    !> Field k of `fields`, required, in (0, hi] or with `zero_ok` in [0, hi].
    subroutine bounded(file, card, fields, k, ctx, zero_ok, hi, expected, value, error)
        character(len=*), intent(in) :: file, ctx, expected
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        logical, intent(in) :: zero_ok
        real(dp), intent(in) :: hi
        real(dp), intent(out) :: value
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: text
        logical :: given, inside
        call get_real(file, card, fields, k, ctx, 0.0_dp, value, error, given)
        if (allocated(error)) return
        inside = value <= hi .and. (value > 0.0_dp .or. (zero_ok .and. value == 0.0_dp))
        if (given .and. inside) return
        call get_text(card, fields, k, text)
        call field_error(error, file, card, fields, k, ctx, expected, text)
    end subroutine bounded

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
end module cfrd_deck_time
