!> MATERIALS: a card naming each material and its law, then the law's parameter cards
!> (ELASTIC one, EB two and optional CREEP and WETTING cards, GOODMAN one,
!> PJOINT one), each read and
!> checked against its layout in the card schema. What is left here is the sequence of the
!> cards and the numbering.
module cfrd_deck_materials
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_model, only: model_t, material_t, law_elastic, law_duncan_eb, law_goodman, &
                          law_pjoint
    use cfrd_cards, only: card_t, get_text, field_error, card_error, upper, is_real, to_text
    use cfrd_card_schema, only: material_fields, elastic_fields, eb_fields, &
                                eb_strength_fields, creep_fields, wetting_fields, &
                                goodman_fields, pjoint_fields
    use cfrd_card_reader, only: card_values_t, read_card
    use cfrd_deck_groups, only: group_cards_t, counts_t, check_numbering, creep_keyword, &
                                wetting_keyword
    implicit none
    private

    public :: read_materials

    !> The laws in the order of the words of field LAW.
    integer, parameter :: laws(4) = [law_elastic, law_duncan_eb, law_goodman, law_pjoint]

contains

    subroutine read_materials(file, group, counts, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(counts_t), intent(in) :: counts
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: number(:), first_card(:), defined(:)
        type(material_t), allocatable :: mats(:)
        type(card_values_t) :: v
        character(len=:), allocatable :: ctx, law
        integer :: i, n, m, limit, nmat
        allocate (number(group%n), first_card(group%n), mats(group%n))
        n = 0
        i = 1
        limit = merge(counts%nmat, group%n, counts%nmat > 0)
        do while (i <= group%n)
            associate (card => group%cards(i))
                law = card_keyword(card)
                if (law == creep_keyword .or. law == wetting_keyword) then
                    ctx = 'a '//law//' card follows the two parameter cards of an EB material'
                    if (law == wetting_keyword) ctx = ctx//' or its CREEP card'
                    if (n > 0) then
                        if (mats(n)%law /= law_duncan_eb) then
                            ctx = ctx//' (MATERIALS '//to_text(number(n))//' is not EB)'
                        else if ((law == creep_keyword .and. mats(n)%creep) .or. &
                                 (law == wetting_keyword .and. mats(n)%wetting)) then
                            ctx = ctx//' (MATERIALS '//to_text(number(n))//' has one already)'
                        else
                            ctx = ctx//' (MATERIALS '//to_text(number(n))//': CREEP '// &
                                  'before WETTING)'
                        end if
                    end if
                    call card_error(error, file, card, ctx)
                    return
                end if
                call read_card(file, card, material_fields, 'MATERIALS', v, error, only=[1])
                if (allocated(error)) return
                m = v%int(1)
                if (m < 1 .or. m > limit) then
                    call field_error(error, file, card, material_fields, 1, 'MATERIALS', &
                                     'a material number from 1 to '//to_text(limit), &
                                     to_text(m))
                    return
                end if
                call read_card(file, card, material_fields, 'MATERIALS '//to_text(m), v, &
                               error, only=[2, 3])
                if (allocated(error)) return
                n = n + 1
                number(n) = m
                first_card(n) = i
                mats(n)%law = laws(v%int(2))
                mats(n)%label = v%text(3)
            end associate
            ctx = 'MATERIALS '//to_text(m)
            if (.not. parameter_cards_follow(mats(n)%law)) return
            select case (mats(n)%law)
            case (law_duncan_eb)
                call read_eb_cards(file, group%cards(i + 1), group%cards(i + 2), ctx, &
                                   model%pa, mats(n), error)
                if (allocated(error)) return
                i = i + 3
                if (i <= group%n) then
                    if (card_keyword(group%cards(i)) == creep_keyword) then
                        call read_creep_card(file, group%cards(i), ctx, mats(n), error)
                        if (allocated(error)) return
                        i = i + 1
                    end if
                end if
                if (i <= group%n) then
                    if (card_keyword(group%cards(i)) == wetting_keyword) then
                        call read_wetting_card(file, group%cards(i), ctx, mats(n), error)
                        if (allocated(error)) return
                        i = i + 1
                    end if
                end if
            case (law_goodman)
                call read_goodman_card(file, group%cards(i + 1), ctx, model, mats(n), error)
                if (allocated(error)) return
                i = i + 2
            case (law_pjoint)
                call read_card(file, group%cards(i + 1), pjoint_fields, ctx, v, error)
                if (allocated(error)) return
                mats(n)%kn_compression = v%x(1)
                mats(n)%kn_tension = v%x(2)
                mats(n)%ks_joint = v%x(3)
                i = i + 2
            case default
                call read_card(file, group%cards(i + 1), elastic_fields, ctx, v, error)
                if (allocated(error)) return
                mats(n)%youngs_modulus = v%x(1)
                mats(n)%poisson_ratio = v%x(2)
                mats(n)%unit_weight = v%x(3)
                mats(n)%tensile_strength = v%x(4)
                i = i + 2
            end select
        end do
        nmat = 0
        if (n > 0) nmat = maxval(number(1:n))
        allocate (defined(nmat), source=0)
        allocate (model%materials(nmat))
        do i = 1, n
            m = number(i)
            if (defined(m) > 0) then
                call card_error(error, file, group%cards(first_card(i)), 'duplicate '// &
                                'material '//to_text(m)//' (first defined at line '// &
                                to_text(group%cards(defined(m))%line)//')')
                return
            end if
            defined(m) = first_card(i)
            model%materials(m) = mats(i)
        end do
        call check_numbering(file, group%header_line, 'material', defined, counts%nmat, &
                             'NMAT', counts%line, error)
    contains
        !> The parameter cards of the law after card i are there (not the end of the group,
        !> not the next material's card 1); else the error that says which is missing.
        logical function parameter_cards_follow(law) result(ok)
            integer, intent(in) :: law
            character(len=:), allocatable :: what
            integer :: k, ncards
            ncards = merge(2, 1, law == law_duncan_eb)
            ok = .false.
            do k = 1, ncards
                if (law == law_duncan_eb) then
                    what = 'parameter card '//to_text(k + 1)//' of law EB'
                else if (law == law_goodman) then
                    what = 'parameter card (KNC, KNT, K1, N1, RF1, PHI, SNMIN, CUTOFF)'
                else if (law == law_pjoint) then
                    what = 'parameter card (KNC, KNT, KS)'
                else
                    what = 'parameter card (E, NU, GAMMA)'
                end if
                if (i + k > group%n) then
                    call card_error(error, file, group%cards(i + k - 1), ctx//': missing '// &
                                    what//' after this card')
                    return
                end if
                if (is_material_card(group%cards(i + k))) then
                    call card_error(error, file, group%cards(i + k), ctx//': missing '// &
                                    what//' before this card')
                    return
                end if
            end do
            ok = .true.
        end function parameter_cards_follow
    end subroutine read_materials

    !> The two parameter cards of an E-B material.
    subroutine read_eb_cards(file, card2, card3, ctx, pa, mat, error)
        character(len=*), intent(in) :: file, ctx
        type(card_t), intent(in) :: card2, card3
        real(dp), intent(in) :: pa
        type(material_t), intent(inout) :: mat
        type(error_t), allocatable, intent(out) :: error
        type(card_values_t) :: v
        call read_card(file, card2, eb_fields, ctx, v, error)
        if (allocated(error)) return
        mat%unit_weight = v%x(1)
        mat%k_modulus = v%x(2)
        mat%n_exponent = v%x(3)
        mat%failure_ratio = v%x(4)
        mat%k_bulk = v%x(5)
        mat%m_exponent = v%x(6)
        mat%k_unload = v%x(7)
        call read_card(file, card3, eb_strength_fields, ctx, v, error, pa=pa)
        if (allocated(error)) return
        mat%phi0 = v%x(1)
        mat%dphi = v%x(2)
        mat%cohesion = v%x(3)
        mat%sigma3_floor = v%x(4)
    end subroutine read_eb_cards

    !> The parameter card of a Goodman joint material.
    subroutine read_goodman_card(file, card, ctx, model, mat, error)
        character(len=*), intent(in) :: file, ctx
        type(card_t), intent(in) :: card
        type(model_t), intent(in) :: model
        type(material_t), intent(inout) :: mat
        type(error_t), allocatable, intent(out) :: error
        type(card_values_t) :: v
        call read_card(file, card, goodman_fields, ctx, v, error, pa=model%pa)
        if (allocated(error)) return
        mat%kn_compression = v%x(1)
        mat%kn_tension = v%x(2)
        mat%k1 = v%x(3)
        mat%n1 = v%x(4)
        mat%rf1 = v%x(5)
        mat%phi = v%x(6)
        mat%sigma_n_floor = v%x(7)
        mat%tension_cutoff = v%int(8) == 1
        mat%gamma_w = model%gamma_w
    end subroutine read_goodman_card

    !> The word in columns 1-10 of a card, upper case: CREEP or WETTING on the cards that
    !> may follow an EB material's two cards (the KEYWORD field of both layouts).
    function card_keyword(card) result(keyword)
        type(card_t), intent(in) :: card
        character(len=:), allocatable :: keyword
        call get_text(card, creep_fields, 1, keyword)
        keyword = upper(keyword)
    end function card_keyword

    !> The CREEP card of an EB material: ALPHA (1/day), B, MC, D, L, each required.
    subroutine read_creep_card(file, card, ctx, mat, error)
        character(len=*), intent(in) :: file, ctx
        type(card_t), intent(in) :: card
        type(material_t), intent(inout) :: mat
        type(error_t), allocatable, intent(out) :: error
        type(card_values_t) :: v
        call read_card(file, card, creep_fields, ctx//' CREEP', v, error, &
                       only=[2, 3, 4, 5, 6])
        if (allocated(error)) return
        mat%creep_alpha = v%x(2)
        mat%creep_b = v%x(3)
        mat%creep_mc = v%x(4)
        mat%creep_d = v%x(5)
        mat%creep_l = v%x(6)
        mat%creep = .true.
    end subroutine read_creep_card

    !> The WETTING card of an EB material: CW, NW, DW, each required (docs/theory.md s. 16).
    subroutine read_wetting_card(file, card, ctx, mat, error)
        character(len=*), intent(in) :: file, ctx
        type(card_t), intent(in) :: card
        type(material_t), intent(inout) :: mat
        type(error_t), allocatable, intent(out) :: error
        type(card_values_t) :: v
        call read_card(file, card, wetting_fields, ctx//' WETTING', v, error, only=[2, 3, 4])
        if (allocated(error)) return
        mat%wet_c = v%x(2)
        mat%wet_n = v%x(3)
        mat%wet_d = v%x(4)
        mat%wetting = .true.
    end subroutine read_wetting_card

    !> A material's first card: its LAW field holds a word.
    logical function is_material_card(card)
        type(card_t), intent(in) :: card
        character(len=:), allocatable :: law, text
        call get_text(card, material_fields, 2, law)
        is_material_card = .false.
        if (len(law) == 0) return
        law = upper(law)
        is_material_card = law(1:1) >= 'A' .and. law(1:1) <= 'Z'
        ! '    2E+004' is an E of 20000 whose exponent letter falls in column 6 (LAW), and
        ! '       inf' a bad E: a fixed-format card whose columns 1-10 read as a real, or
        ! whose M (columns 1-5) is blank, is a parameter card.
        if (is_material_card .and. .not. card%free) then
            call get_text(card, elastic_fields, 1, text)
            is_material_card = .not. is_real(text)
            call get_text(card, material_fields, 1, text)
            is_material_card = is_material_card .and. len(text) > 0
        end if
    end function is_material_card
end module cfrd_deck_materials
