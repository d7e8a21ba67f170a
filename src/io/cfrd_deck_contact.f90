!> CONTACT: SURFACE cards (element faces, generated with NGEN and INC; cards of one name
!> add up) and PAIR cards (slave, master, friction, closure tolerance, scheme, search, cast
!> in place, roles); docs/cards.md, CONTACT. The fields are read and checked against the card
!> schema; here remain the checks against the mesh and between the surfaces, and the roles
!> (cfrd_contact_roles: a much finer slave made the master).
module cfrd_deck_contact
    use cfrd_error, only: error_t, fatal_error, input_error
    use cfrd_model, only: model_t, contact_surface_t, contact_pair_t, scheme_mortar, &
                          scheme_nts, search_linear, search_rpim, is_joint_kind
    use cfrd_cards, only: field_error, card_error, upper, to_text
    use cfrd_card_schema, only: surface_fields, pair_fields
    use cfrd_contact_roles, only: assign_roles
    use cfrd_card_reader, only: card_values_t, read_card, raw_text
    use cfrd_deck_groups, only: group_cards_t
    implicit none
    private

    public :: read_contact

    !> The schemes and searches in the order of the words of fields SCHEME and SEARCH.
    integer, parameter :: schemes(2) = [scheme_mortar, scheme_nts]
    integer, parameter :: searches(2) = [search_linear, search_rpim]

contains

    !> The CONTACT group into model%surfaces and model%contact_pairs.
    subroutine read_contact(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: name, ctx
        integer, allocatable :: first_line(:), used_as(:), owner(:)
        integer :: i, k, e, face, ngen, inc, s, node, side, j
        type(contact_pair_t) :: pair
        type(card_values_t) :: v
        allocate (model%surfaces(0), model%contact_pairs(0), first_line(0))
        if (.not. group%present) return
        if (group%n == 0) then
            call fatal_error(error, file//':'//to_text(group%header_line)//': CONTACT has '// &
                             'no SURFACE or PAIR cards', input_error)
            return
        end if
        do i = 1, group%n
            associate (card => group%cards(i))
                if (upper(raw_text(card, surface_fields, 1)) /= 'SURFACE') cycle
                call read_card(file, card, surface_fields, 'CONTACT SURFACE', v, error, &
                               only=[2])
                if (allocated(error)) return
                name = upper(v%text(2))
                ctx = 'CONTACT SURFACE '//name
                s = surface_index(name)
                if (s == 0) then
                    model%surfaces = [model%surfaces, contact_surface_t(name=name)]
                    s = size(model%surfaces)
                    allocate (model%surfaces(s)%element(0), model%surfaces(s)%face(0))
                    first_line = [first_line, card%line]
                end if
                call read_card(file, card, surface_fields, ctx, v, error, only=[3, 4, 5, 6])
                if (allocated(error)) return
                e = v%int(3)
                face = v%int(4)
                ngen = v%int(5)
                inc = v%int(6)
                if (inc == 0) then
                    call field_error(error, file, card, surface_fields, 6, ctx, &
                                     'a non-zero increment', raw_text(card, surface_fields, 6))
                    return
                end if
                do k = 0, ngen
                    if (e + k*inc < 1 .or. e + k*inc > model%mesh%nelem) then
                        call field_error(error, file, card, surface_fields, &
                                         merge(3, 5, k == 0), ctx, 'elements from 1 to '// &
                                         to_text(model%mesh%nelem)//' (generated element '// &
                                         to_text(e + k*inc)//' is not)', &
                                         raw_text(card, surface_fields, merge(3, 5, k == 0)))
                        return
                    end if
                    if (is_joint_kind(model%mesh%kind(e + k*inc))) then
                        call field_error(error, file, card, surface_fields, 3, ctx, &
                                         'a solid element (element '//to_text(e + k*inc)// &
                                         ' is a joint)', raw_text(card, surface_fields, 3))
                        return
                    end if
                    associate (conn => model%mesh%conn(:, e + k*inc))
                        if (face == 3 .and. conn(3) == conn(4)) then
                            call field_error(error, file, card, surface_fields, 4, ctx, &
                                             'face 1, 2 or 4: element '//to_text(e + k*inc)// &
                                             ' is a triangle, its face 3 has zero length', '3')
                            return
                        end if
                    end associate
                    if (any(model%surfaces(s)%element == e + k*inc .and. &
                            model%surfaces(s)%face == face)) then
                        call card_error(error, file, card, 'face '//to_text(face)// &
                                        ' of element '//to_text(e + k*inc)//' is twice in '// &
                                        'surface '//name)
                        return
                    end if
                    model%surfaces(s)%element = [model%surfaces(s)%element, e + k*inc]
                    model%surfaces(s)%face = [model%surfaces(s)%face, face]
                end do
            end associate
        end do
        allocate (used_as(size(model%surfaces)), source=0)
        do i = 1, group%n
            associate (card => group%cards(i))
                if (upper(raw_text(card, pair_fields, 1)) /= 'PAIR') cycle
                pair = contact_pair_t(line=card%line)
                do side = 2, 3
                    name = raw_text(card, pair_fields, side)
                    s = surface_index(upper(name))
                    if (s == 0) then
                        call field_error(error, file, card, pair_fields, side, 'CONTACT PAIR', &
                                         'a surface named on a SURFACE card ('// &
                                         surface_list()//')', name)
                        return
                    end if
                    if (used_as(s) /= 0) then
                        call field_error(error, file, card, pair_fields, side, 'CONTACT PAIR', &
                                         'a surface in no other pair (line '// &
                                         to_text(used_as(s))//')', name)
                        return
                    end if
                    used_as(s) = card%line
                    if (side == 2) pair%slave = s
                    if (side == 3) pair%master = s
                end do
                ctx = 'CONTACT PAIR '//trim(model%surfaces(pair%slave)%name)
                call read_card(file, card, pair_fields, ctx, v, error, only=[4, 5, 6, 7])
                if (allocated(error)) return
                pair%friction = v%x(4)
                pair%tolerance = v%x(5)
                pair%scheme = schemes(v%int(6))
                pair%search = searches(v%int(7))
                if (pair%search == search_rpim .and. pair%scheme == scheme_nts) then
                    call field_error(error, file, card, pair_fields, 7, ctx, &
                                     'LINEAR with SCHEME NTS (RPIM serves the mortar '// &
                                     'scheme)', v%text(7))
                    return
                end if
                call read_card(file, card, pair_fields, ctx, v, error, only=[8, 9])
                if (allocated(error)) return
                pair%cast = v%int(8) == 1
                pair%roles_asis = v%int(9) == 2
                ! Two independent bodies: no node on both surfaces.
                allocate (owner(model%mesh%nnode), source=0)
                do j = 1, size(model%surfaces(pair%slave)%element)
                    call face_nodes(model%surfaces(pair%slave), j, owner, 1, node)
                end do
                do j = 1, size(model%surfaces(pair%master)%element)
                    call face_nodes(model%surfaces(pair%master), j, owner, 2, node)
                    if (node > 0) then
                        call card_error(error, file, card, 'node '//to_text(node)//' is on '// &
                                        'both surfaces '//trim(model%surfaces(pair%slave)%name)// &
                                        ' and '//trim(model%surfaces(pair%master)%name)// &
                                        ': contact is between independent bodies (give '// &
                                        'each its own nodes)')
                        return
                    end if
                end do
                deallocate (owner)
                call assign_roles(model, pair)
                model%contact_pairs = [model%contact_pairs, pair]
            end associate
        end do
        do s = 1, size(model%surfaces)
            if (used_as(s) == 0) then
                call fatal_error(error, file//':'//to_text(first_line(s))//': surface '// &
                                 trim(model%surfaces(s)%name)//' is in no CONTACT PAIR', &
                                 input_error)
                return
            end if
        end do
    contains
        integer function surface_index(surface_name)
            character(len=*), intent(in) :: surface_name
            integer :: m
            surface_index = 0
            do m = 1, size(model%surfaces)
                if (model%surfaces(m)%name == surface_name) surface_index = m
            end do
        end function surface_index

        function surface_list() result(text)
            character(len=:), allocatable :: text
            integer :: m
            text = ''
            do m = 1, size(model%surfaces)
                if (m > 1) text = text//', '
                text = text//trim(model%surfaces(m)%name)
            end do
        end function surface_list

        !> Mark the two nodes of face j of a surface with `mark`; `clash` is a node that
        !> already carried the other mark (0 if none).
        subroutine face_nodes(surface, j, marks, mark, clash)
            type(contact_surface_t), intent(in) :: surface
            integer, intent(in) :: j, mark
            integer, intent(inout) :: marks(:)
            integer, intent(out) :: clash
            integer :: ends(2), q
            ends = [model%mesh%conn(surface%face(j), surface%element(j)), &
                    model%mesh%conn(mod(surface%face(j), 4) + 1, surface%element(j))]
            clash = 0
            do q = 1, 2
                if (marks(ends(q)) /= 0 .and. marks(ends(q)) /= mark) clash = ends(q)
                marks(ends(q)) = mark
            end do
        end subroutine face_nodes
    end subroutine read_contact
end module cfrd_deck_contact
