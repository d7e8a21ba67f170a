!> INTERFACE, SLAB and PLINTH: the lines of node pairs between the face slab and the cushion, whose
!> joints or thin layers are appended to the mesh, and the element groups of the face slab.
!> The fields are read and checked against the card schema; here remain the checks against
!> the mesh and materials, the generation of pairs and the geometry of the new elements.
module cfrd_deck_interface
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, input_error
    use cfrd_model, only: model_t, mesh_t, is_joint_law, elem_quad4, elem_joint_gauss, &
                          elem_joint_lobatto, interface_element_t, method_joint, method_thin, &
                          is_joint_kind
    use cfrd_model_check, only: layer_thickness
    use cfrd_cards, only: field_error, card_error, upper, to_text, field_t
    use cfrd_card_schema, only: interface_fields, slab_fields, plinth_fields
    use cfrd_card_reader, only: card_values_t, read_card, raw_text, position, group_list
    use cfrd_deck_groups, only: group_cards_t
    implicit none
    private

    public :: read_interface, read_slab, read_plinth

    !> The methods in the order of the words of field TYPE.
    integer, parameter :: methods(2) = [method_joint, method_thin]

contains

    !> INTERFACE: lines of node pairs (bottom = cushion side, top = slab side); the elements
    !> between consecutive pairs of a line, joints or thin-layer quads, are appended to the
    !> mesh after the ELEMENTS (docs/cards.md).
    subroutine read_interface(file, group, model, element_line, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        integer, allocatable, intent(inout) :: element_line(:)
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: pair_line(:), pair_bottom(:), pair_top(:), pair_card(:), &
                                card_mat(:), card_kind(:), card_method(:), card_group(:), &
                                lines(:), new_conn(:, :), new_cards(:, :)
        character(len=:), allocatable :: ctx, text
        type(card_values_t) :: v
        integer :: i, g, line, nb, nt, ngen, incb, inct, k, np, a, b, nnew, e, nelem0, c
        real(dp) :: t(2), nrm(2), length, gap, centre(2)
        allocate (model%interfaces(0))
        if (.not. group%present) return
        if (group%n == 0) then
            call fatal_error(error, file//':'//to_text(group%header_line)//': INTERFACE '// &
                             'has no node-pair cards', input_error)
            return
        end if
        allocate (pair_line(0), pair_bottom(0), pair_top(0), pair_card(0), lines(0))
        allocate (card_mat(group%n), card_kind(group%n), card_method(group%n), &
                  card_group(group%n))
        do i = 1, group%n
            associate (card => group%cards(i))
                call read_card(file, card, interface_fields, 'INTERFACE', v, error, only=[1])
                if (allocated(error)) return
                line = v%int(1)
                ctx = 'INTERFACE line '//to_text(line)
                call read_card(file, card, interface_fields, ctx, v, error, only=[4, 5, 6])
                if (allocated(error)) return
                ngen = v%int(4)
                incb = v%int(5)
                inct = v%int(6)
                do k = 2, 3
                    call read_card(file, card, interface_fields, ctx, v, error, only=[k])
                    if (allocated(error)) return
                    a = v%int(k)
                    b = v%int(k) + ngen*merge(incb, inct, k == 2)
                    if (min(a, b) < 1 .or. max(a, b) > model%mesh%nnode) then
                        call field_error(error, file, card, interface_fields, k, ctx, &
                                         'a node from 1 to '//to_text(model%mesh%nnode)// &
                                         trim(merge(' for every generated pair', &
                                                    '                         ', ngen > 0)), &
                                         raw_text(card, interface_fields, k))
                        return
                    end if
                end do
                nb = v%int(2)
                nt = v%int(3)
                if (nb == nt .or. (ngen > 0 .and. (incb == 0 .or. inct == 0))) then
                    call card_error(error, file, card, ctx//': the bottom and top nodes of '// &
                                    'a pair must differ, and INCB, INCT must not be 0')
                    return
                end if
                call read_card(file, card, interface_fields, ctx, v, error, only=[7])
                if (allocated(error)) return
                card_mat(i) = v%int(7)
                if (card_mat(i) < 1 .or. card_mat(i) > size(model%materials)) then
                    call field_error(error, file, card, interface_fields, 7, ctx, &
                                     'a material number from 1 to '// &
                                     to_text(size(model%materials)), &
                                     raw_text(card, interface_fields, 7))
                    return
                end if
                call read_card(file, card, interface_fields, ctx, v, error, only=[8, 9, 10])
                if (allocated(error)) return
                card_method(i) = methods(v%int(8))
                if (is_joint_law(model%materials(card_mat(i))%law) .neqv. &
                    (card_method(i) == method_joint)) then
                    call field_error(error, file, card, interface_fields, 7, ctx, &
                                     trim(merge('a GOODMAN or PJOINT material for a JOINT', &
                                                'a solid material (not a joint) for THIN ', &
                                                card_method(i) == method_joint)), &
                                     raw_text(card, interface_fields, 7))
                    return
                end if
                text = upper(v%text(9))
                card_kind(i) = elem_quad4
                if (card_method(i) == method_joint) then
                    select case (text)
                    case ('', 'LOBATTO', 'NEWTON')
                        card_kind(i) = elem_joint_lobatto
                    case ('GAUSS')
                        card_kind(i) = elem_joint_gauss
                    case default
                        call field_error(error, file, card, interface_fields, 9, ctx, &
                                         'an integration rule: GAUSS or LOBATTO (blank: '// &
                                         'LOBATTO, the 2-point Newton-Cotes rule)', text)
                        return
                    end select
                else if (len(text) > 0) then
                    call field_error(error, file, card, interface_fields, 9, ctx, &
                                     'blank: a THIN layer is a quad with its 2x2 Gauss rule', &
                                     text)
                    return
                end if
                text = upper(v%text(10))
                card_group(i) = 0
                if (len(text) > 0) then
                    card_group(i) = position(model%mesh%group_name, text)
                    if (card_group(i) == 0) then
                        model%mesh%group_name = [character(len=10) :: model%mesh%group_name, &
                                                 text]
                        card_group(i) = size(model%mesh%group_name)
                    end if
                end if
                do g = 0, ngen
                    pair_line = [pair_line, line]
                    pair_bottom = [pair_bottom, nb + g*incb]
                    pair_top = [pair_top, nt + g*inct]
                    pair_card = [pair_card, i]
                end do
                if (.not. any(lines == line)) lines = [lines, line]
            end associate
        end do
        ! Elements between consecutive pairs of each line, lines in order of appearance.
        nelem0 = model%mesh%nelem
        allocate (new_conn(4, 0), new_cards(2, 0))
        do k = 1, size(lines)
            np = 0
            a = 0
            do i = 1, size(pair_line)
                if (pair_line(i) /= lines(k)) cycle
                np = np + 1
                if (a > 0) then
                    c = pair_card(a)
                    new_conn = reshape([new_conn, pair_bottom(a), pair_bottom(i), pair_top(i), &
                                        pair_top(a)], [4, size(new_conn, 2) + 1])
                    new_cards = reshape([new_cards, pair_card(a), pair_card(i)], &
                                        [2, size(new_cards, 2) + 1])
                    model%interfaces = [model%interfaces, interface_element_t( &
                                        element=nelem0 + size(new_conn, 2), line=lines(k), &
                                        method=card_method(c))]
                    model%mesh%kind = [model%mesh%kind, card_kind(c)]
                    model%mesh%material = [model%mesh%material, card_mat(c)]
                    model%mesh%group = [model%mesh%group, card_group(c)]
                    element_line = [element_line, group%cards(c)%line]
                end if
                a = i
            end do
            if (np < 2) then
                call card_error(error, file, group%cards(pair_card(a)), 'INTERFACE line '// &
                                to_text(lines(k))//' has one node pair: a line needs two or '// &
                                'more (one element between each two consecutive pairs)')
                return
            end if
        end do
        nnew = size(new_conn, 2)
        model%mesh%conn = reshape([model%mesh%conn, new_conn], [4, nelem0 + nnew])
        model%mesh%nelem = nelem0 + nnew
        ! Geometry: joints of zero thickness, every element with its top side on the left.
        do k = 1, nnew
            e = nelem0 + k
            associate (x => model%mesh%x, conn => model%mesh%conn(:, e))
                ctx = 'INTERFACE line '//to_text(model%interfaces(k)%line)//', pairs '// &
                      to_text(conn(1))//'/'//to_text(conn(4))//' and '//to_text(conn(2))// &
                      '/'//to_text(conn(3))
                t = x(:, conn(2)) - x(:, conn(1))
                length = norm2(t)
                if (length <= 0.0_dp) then
                    call fatal_error(error, file//':'//to_text(element_line(e))//': '//ctx// &
                                     ': the two bottom nodes coincide (zero length)', &
                                     input_error)
                    return
                end if
                t = t/length
                nrm = [-t(2), t(1)]
                if (model%interfaces(k)%method == method_joint) then
                    ! A pair whose nodes do not coincide: the error of its card's NT field.
                    do c = 1, 2
                        a = merge(1, 2, c == 1)
                        b = merge(4, 3, c == 1)
                        gap = norm2(x(:, conn(b)) - x(:, conn(a)))
                        if (gap > 1.0e-6_dp*length) then
                            call field_error(error, file, group%cards(new_cards(c, k)), &
                                             interface_fields, 3, 'INTERFACE line '// &
                                             to_text(model%interfaces(k)%line), &
                                             'a top node at its bottom node (pair '// &
                                             to_text(conn(a))//'/'//to_text(conn(b))// &
                                             ': the nodes are '//trim(real_text_of(gap))// &
                                             ' m apart; a JOINT has zero thickness, use '// &
                                             'THIN for a layer)', &
                                             raw_text(group%cards(new_cards(c, k)), &
                                                      interface_fields, 3))
                            return
                        end if
                    end do
                    ! The top nodes' solid elements must lie on the left (along n).
                    centre = solid_centre(model%mesh, conn(4), nelem0)
                    if (norm2(centre) < huge(1.0_dp) .and. &
                        dot_product(centre - x(:, conn(1)), nrm) < 0.0_dp) then
                        call fatal_error(error, file//':'//to_text(element_line(e))//': '// &
                                         ctx//': the top nodes'' elements lie on the right '// &
                                         'of the line from bottom node '//to_text(conn(1))// &
                                         ' to '//to_text(conn(2))//'; list the pairs of '// &
                                         'the line in the opposite order', input_error)
                        return
                    end if
                else if (cross(t, x(:, conn(4)) - x(:, conn(1))) <= 0.0_dp .or. &
                         cross(t, x(:, conn(3)) - x(:, conn(2))) <= 0.0_dp) then
                    call fatal_error(error, file//':'//to_text(element_line(e))//': '//ctx// &
                                     ': the top nodes lie on the right of (or on) the line '// &
                                     'from bottom node '//to_text(conn(1))//' to '// &
                                     to_text(conn(2))//'; list the pairs of the line in '// &
                                     'the opposite order', input_error)
                    return
                end if
            end associate
        end do
        call thin_layer_warnings(model)
    contains
        pure real(dp) function cross(p, q)
            real(dp), intent(in) :: p(2), q(2)
            cross = p(1)*q(2) - p(2)*q(1)
        end function cross

        function real_text_of(value) result(text)
            real(dp), intent(in) :: value
            character(len=16) :: text
            write (text, '(es10.3)') value
            text = adjustl(text)
        end function real_text_of

        !> Centroid of the first solid element (ELEMENTS) that uses `node`, huge if none.
        pure function solid_centre(mesh, node, nsolid) result(centre)
            type(mesh_t), intent(in) :: mesh
            integer, intent(in) :: node, nsolid
            real(dp) :: centre(2)
            integer :: j
            centre = huge(1.0_dp)
            do j = 1, nsolid
                if (any(mesh%conn(:, j) == node)) then
                    centre = sum(mesh%x(:, mesh%conn(:, j)), dim=2)/4.0_dp
                    return
                end if
            end do
        end function solid_centre
    end subroutine read_interface

    !> Warn (the run goes on) when a thin layer's thickness / length lies outside 0.01-0.1,
    !> the range in which thin layers model slip well (Desai et al. 1984; paper section 2.3).
    subroutine thin_layer_warnings(model)
        type(model_t), intent(inout) :: model
        character(len=:), allocatable :: outside
        real(dp) :: ratio, lo, hi
        integer :: k, count_out
        outside = ''
        count_out = 0
        lo = huge(1.0_dp)
        hi = 0.0_dp
        do k = 1, size(model%interfaces)
            if (model%interfaces(k)%method /= method_thin) cycle
            ratio = thin_aspect(model%mesh, model%interfaces(k)%element)
            if (ratio >= 0.01_dp*(1.0_dp - 1.0e-9_dp) .and. ratio <= 0.1_dp*(1.0_dp + 1.0e-9_dp)) cycle
            count_out = count_out + 1
            lo = min(lo, ratio)
            hi = max(hi, ratio)
            if (count_out <= 20) outside = outside//' '//to_text(model%interfaces(k)%element)
        end do
        if (count_out == 0) return
        if (count_out > 20) outside = outside//' ...'
        block
            character(len=300) :: text
            character(len=24) :: range
            write (range, '(f0.4,a,f0.4)') lo, ' to ', hi
            text = to_text(count_out)//' thin-layer element(s) with thickness / length '// &
                   trim(range)//', outside 0.01-0.1 (Desai et al. 1984): elements'//outside
            model%warnings = [character(len=300) :: model%warnings, text]
        end block
    end subroutine thin_layer_warnings

    !> Thickness / length of the thin-layer quad e (length: mean of faces 1-2 and 3-4).
    pure real(dp) function thin_aspect(mesh, e) result(ratio)
        type(mesh_t), intent(in) :: mesh
        integer, intent(in) :: e
        real(dp) :: p(2, 4)
        p = mesh%x(:, mesh%conn(:, e))
        ratio = layer_thickness(p)/(0.5_dp*(norm2(p(:, 2) - p(:, 1)) + norm2(p(:, 3) - p(:, 4))))
    end function thin_aspect

    !> SLAB: the element groups that form the face slab, whose stresses are tabulated along
    !> the slab axis (the groups' interface elements, placed with the slab, are left out).
    subroutine read_slab(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        call read_group_names(file, group, 'SLAB', slab_fields, model, model%slab_groups, error)
    end subroutine read_slab

    !> PLINTH: the element groups of the plinth, the concrete body on the rock that the
    !> perimetric joint joins to the slab. Read after BOUNDARY: each of its solid elements
    !> must lie on the base, with a side whose two nodes are held in x and y.
    subroutine read_plinth(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        integer :: e, k, a, b
        logical :: on_base
        call read_group_names(file, group, 'PLINTH', plinth_fields, model, &
                              model%plinth_groups, error)
        if (allocated(error)) return
        do e = 1, model%mesh%nelem
            if (.not. any(model%plinth_groups == model%mesh%group(e))) cycle
            if (model%mesh%group(e) == 0) cycle
            on_base = .false.
            do k = 1, 4
                a = model%mesh%conn(k, e)
                b = model%mesh%conn(mod(k, 4) + 1, e)
                if (a == b) cycle
                on_base = on_base .or. (all(model%fixed(:, a)) .and. all(model%fixed(:, b)))
            end do
            if (is_joint_kind(model%mesh%kind(e))) on_base = .false.
            if (.not. on_base) then
                k = findloc(model%plinth_groups, model%mesh%group(e), dim=1)
                call field_error(error, file, group%cards(k), plinth_fields, 1, 'PLINTH', &
                                 'a group whose every element lies on the base (element '// &
                                 to_text(e)//' has no side whose two nodes BOUNDARY '// &
                                 'holds in x and y)', trim(model%mesh%group_name( &
                                 model%mesh%group(e))))
                return
            end if
        end do
    end subroutine read_plinth

    !> The cards of a group that each name an element group (SLAB, PLINTH): `groups`, the
    !> groups' indices in the order of the cards.
    subroutine read_group_names(file, group, what, fields, model, groups, error)
        character(len=*), intent(in) :: file, what
        type(group_cards_t), intent(in) :: group
        type(field_t), intent(in) :: fields(:)
        type(model_t), intent(in) :: model
        integer, allocatable, intent(out) :: groups(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: name
        integer :: i, g
        allocate (groups(0))
        if (group%present .and. group%n == 0) then
            call fatal_error(error, file//':'//to_text(group%header_line)//': '//what// &
                             ' has no group cards', input_error)
            return
        end if
        do i = 1, group%n
            associate (card => group%cards(i))
                name = raw_text(card, fields, 1)
                g = position(model%mesh%group_name, upper(name))
                if (g == 0) then
                    call field_error(error, file, card, fields, 1, what, &
                                     'an element group ('//group_list(model%mesh%group_name)// &
                                     ')', name)
                    return
                end if
                if (any(groups == g)) then
                    call field_error(error, file, card, fields, 1, what, &
                                     'a group not listed before', name)
                    return
                end if
                groups = [groups, g]
            end associate
        end do
    end subroutine read_group_names
end module cfrd_deck_interface
