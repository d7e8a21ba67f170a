!> NODES and ELEMENTS: the mesh, with the generation of node lines and element rows. The
!> fields are read and checked against the card schema; here remain the checks against other
!> cards (numbers in range, nodes that exist, materials) and the generation.
module cfrd_deck_mesh
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_model, only: model_t, is_joint_law, law_name, elem_quad4, elem_quad4_shear
    use cfrd_cards, only: card_t, field_t, field_error, card_error, upper, to_text
    use cfrd_card_schema, only: node_fields, element_fields
    use cfrd_card_reader, only: card_values_t, read_card, raw_text, position
    use cfrd_deck_groups, only: group_cards_t, counts_t, check_numbering, max_number
    implicit none
    private

    public :: read_nodes, read_elements, get_range

    !> The element kinds in the order of the words of field TYPE.
    integer, parameter :: element_kinds(2) = [elem_quad4, elem_quad4_shear]

contains

    subroutine read_nodes(file, group, counts, model, node_line, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(counts_t), intent(in) :: counts
        type(model_t), intent(inout) :: model
        integer, allocatable, intent(out) :: node_line(:)
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: n1(:), n2(:), inc(:)
        real(dp), allocatable :: p1(:, :), p2(:, :)
        type(card_values_t) :: v
        integer :: i, k, steps, node, limit, nnode
        character(len=:), allocatable :: ctx
        allocate (n1(group%n), n2(group%n), inc(group%n), p1(2, group%n), p2(2, group%n))
        limit = merge(counts%nnode, max_number, counts%nnode > 0)
        do i = 1, group%n
            associate (card => group%cards(i))
                call get_range(file, card, node_fields, 'NODES', 'node', limit, v, &
                               n1(i), n2(i), inc(i), error)
                if (allocated(error)) return
                ctx = 'NODES '//to_text(n1(i))
                ! The four coordinates are read before any is checked.
                call read_card(file, card, node_fields, ctx, v, error, only=[4, 5, 6, 7], &
                               parse_first=.true.)
                if (allocated(error)) return
                p1(:, i) = v%x(4:5)
                p2(:, i) = v%x(6:7)
                if (n2(i) > n1(i) .and. .not. (v%given(6) .and. v%given(7))) then
                    k = merge(7, 6, v%given(6))
                    call field_error(error, file, card, node_fields, k, ctx, &
                                     'the coordinate of the last node N2 = '//to_text(n2(i)), &
                                     '')
                    return
                end if
            end associate
        end do
        nnode = 0
        if (group%n > 0) nnode = maxval(n2)
        allocate (model%mesh%x(2, nnode), node_line(nnode))
        node_line = 0
        do i = 1, group%n
            steps = (n2(i) - n1(i))/inc(i)
            do k = 0, steps
                node = n1(i) + k*inc(i)
                if (node_line(node) > 0) then
                    call card_error(error, file, group%cards(i), 'duplicate node '// &
                                    to_text(node)//' (first defined at line '// &
                                    to_text(node_line(node))//')')
                    return
                end if
                node_line(node) = group%cards(i)%line
                if (steps == 0) then
                    model%mesh%x(:, node) = p1(:, i)
                else
                    model%mesh%x(:, node) = p1(:, i) + (p2(:, i) - p1(:, i))*real(k, dp)/steps
                end if
            end do
        end do
        model%mesh%nnode = nnode
        call check_numbering(file, group%header_line, 'node', node_line, counts%nnode, &
                             'NNODE', counts%line, error)
    end subroutine read_nodes

    !> Fields N1, N2, INC (fields offset+1 to offset+3 of `fields`) of a node-range card into
    !> `v`, checked: 1 <= N1 <= N2 <= limit, INC > 0 dividing N2 - N1.
    subroutine get_range(file, card, fields, group_name, what, limit, v, n1, n2, inc, error, &
                         offset)
        character(len=*), intent(in) :: file, group_name, what
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: limit
        type(card_values_t), intent(inout) :: v
        integer, intent(out) :: n1, n2, inc
        type(error_t), allocatable, intent(out) :: error
        integer, intent(in), optional :: offset
        integer :: f
        f = 0
        if (present(offset)) f = offset
        call read_card(file, card, fields, group_name, v, error, only=[f + 1])
        if (allocated(error)) return
        n1 = v%int(f + 1)
        if (n1 < 1 .or. n1 > limit) then
            call field_error(error, file, card, fields, f + 1, group_name, &
                             'a '//what//' number from 1 to '//to_text(limit), &
                             raw_text(card, fields, f + 1))
            return
        end if
        call read_card(file, card, fields, group_name, v, error, only=[f + 2])
        if (allocated(error)) return
        n2 = v%int(f + 2)
        if (n2 < n1 .or. n2 > limit) then
            call field_error(error, file, card, fields, f + 2, group_name, &
                             'a last '//what//' from N1 = '//to_text(n1)//' to '// &
                             to_text(limit), raw_text(card, fields, f + 2))
            return
        end if
        call read_card(file, card, fields, group_name, v, error, only=[f + 3])
        if (allocated(error)) return
        inc = v%int(f + 3)
        if (mod(n2 - n1, inc) /= 0) then
            call field_error(error, file, card, fields, f + 3, group_name, &
                             'an increment that divides N2 - N1 = '//to_text(n2 - n1), &
                             raw_text(card, fields, f + 3))
            return
        end if
    end subroutine get_range

    subroutine read_elements(file, group, counts, model, element_line, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(counts_t), intent(in) :: counts
        type(model_t), intent(inout) :: model
        integer, allocatable, intent(out) :: element_line(:)
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: first(:), nodes(:, :), mat(:), ngen(:), ninc(:), grp(:), &
                                kinds(:)
        character(len=10), allocatable :: names(:)
        character(len=:), allocatable :: name, ctx
        type(card_values_t) :: v
        integer :: i, k, g, e, limit, nelem, nnode, a, b
        allocate (first(group%n), nodes(4, group%n), mat(group%n), ngen(group%n), &
                  ninc(group%n), grp(group%n), kinds(group%n), names(0))
        limit = merge(counts%nelem, max_number, counts%nelem > 0)
        nnode = model%mesh%nnode
        do i = 1, group%n
            associate (card => group%cards(i))
                call read_card(file, card, element_fields, 'ELEMENTS', v, error, only=[1])
                if (allocated(error)) return
                first(i) = v%int(1)
                if (first(i) < 1 .or. first(i) > limit) then
                    call field_error(error, file, card, element_fields, 1, 'ELEMENTS', &
                                     'an element number from 1 to '//to_text(limit), &
                                     raw_text(card, element_fields, 1))
                    return
                end if
                ctx = 'ELEMENTS '//to_text(first(i))
                call read_card(file, card, element_fields, ctx, v, error, only=[7])
                if (allocated(error)) return
                ngen(i) = v%int(7)
                if (ngen(i) < 0 .or. first(i) + ngen(i) > limit) then
                    call field_error(error, file, card, element_fields, 7, ctx, &
                                     'a count from 0 to '//to_text(limit - first(i)), &
                                     raw_text(card, element_fields, 7))
                    return
                end if
                call read_card(file, card, element_fields, ctx, v, error, only=[8])
                if (allocated(error)) return
                ninc(i) = v%int(8)
                do k = 1, 4
                    call read_card(file, card, element_fields, ctx, v, error, only=[k + 1])
                    if (allocated(error)) return
                    nodes(k, i) = v%int(k + 1)
                    if (k == 4 .and. nodes(4, i) == 0) nodes(4, i) = nodes(3, i)
                    ! Every generated element's node must exist too.
                    a = nodes(k, i)
                    b = nodes(k, i) + ngen(i)*ninc(i)
                    if (min(a, b) < 1 .or. max(a, b) > nnode) then
                        call field_error(error, file, card, element_fields, k + 1, ctx, &
                                         'a node from 1 to '//to_text(nnode)// &
                                         trim(merge(' for every generated element', &
                                                    '                            ', &
                                                    ngen(i) > 0)), &
                                         raw_text(card, element_fields, k + 1))
                        return
                    end if
                end do
                if (nodes(1, i) == nodes(2, i) .or. nodes(1, i) == nodes(3, i) .or. &
                    nodes(2, i) == nodes(3, i) .or. nodes(4, i) == nodes(1, i) .or. &
                    nodes(4, i) == nodes(2, i)) then
                    call card_error(error, file, card, 'element '//to_text(first(i))// &
                                    ' repeats a node: nodes must be distinct '// &
                                    '(L = K or blank makes a triangle)')
                    return
                end if
                call read_card(file, card, element_fields, ctx, v, error, only=[6])
                if (allocated(error)) return
                mat(i) = v%int(6)
                if (mat(i) < 1 .or. mat(i) > size(model%materials)) then
                    call field_error(error, file, card, element_fields, 6, ctx, &
                                     'a material number from 1 to '// &
                                     to_text(size(model%materials)), &
                                     raw_text(card, element_fields, 6))
                    return
                end if
                if (is_joint_law(model%materials(mat(i))%law)) then
                    call field_error(error, file, card, element_fields, 6, ctx, &
                                     'a solid material: '// &
                                     law_name(model%materials(mat(i))%law)// &
                                     ' is the law of joints, '// &
                                     'given on INTERFACE cards', raw_text(card, element_fields, 6))
                    return
                end if
                call read_card(file, card, element_fields, ctx, v, error, only=[10, 9])
                if (allocated(error)) return
                kinds(i) = element_kinds(v%int(10))
                name = upper(v%text(9))
                grp(i) = 0
                if (len(name) > 0) then
                    grp(i) = position(names, name)
                    if (grp(i) == 0) then
                        names = [character(len=10) :: names, name]
                        grp(i) = size(names)
                    end if
                end if
            end associate
        end do
        nelem = 0
        do i = 1, group%n
            nelem = max(nelem, first(i) + ngen(i))
        end do
        associate (mesh => model%mesh)
            mesh%nelem = nelem
            allocate (mesh%conn(4, nelem), mesh%material(nelem), mesh%group(nelem))
            allocate (mesh%kind(nelem), source=elem_quad4)
            mesh%group_name = names
            allocate (element_line(nelem), source=0)
            do i = 1, group%n
                do g = 0, ngen(i)
                    e = first(i) + g
                    if (element_line(e) > 0) then
                        call card_error(error, file, group%cards(i), 'duplicate element '// &
                                        to_text(e)//' (first defined at line '// &
                                        to_text(element_line(e))//')')
                        return
                    end if
                    element_line(e) = group%cards(i)%line
                    mesh%conn(:, e) = nodes(:, i) + g*ninc(i)
                    mesh%material(e) = mat(i)
                    mesh%group(e) = grp(i)
                    mesh%kind(e) = kinds(i)
                end do
            end do
        end associate
        call check_numbering(file, group%header_line, 'element', element_line, counts%nelem, &
                             'NELEM', counts%line, error)
    end subroutine read_elements
end module cfrd_deck_mesh
