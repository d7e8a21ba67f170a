!> BOUNDARY and LOADS: prescribed displacements and the load sets (GRAVITY, FORCE,
!> PRESSURE). The fields are read and checked against the card schema; here remain the
!> checks against the mesh (nodes, elements, faces, groups).
module cfrd_deck_loads
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_model, only: model_t, gravity_load_t, pressure_load_t, load_set_t, all_groups, &
                          is_joint_kind
    use cfrd_cards, only: card_t, get_text, field_error, card_error, upper, to_text
    use cfrd_card_schema, only: boundary_fields, gravity_fields, force_fields, pressure_fields
    use cfrd_card_reader, only: card_values_t, read_card, raw_text, position, group_list
    use cfrd_deck_groups, only: group_cards_t
    use cfrd_deck_mesh, only: get_range
    implicit none
    private

    public :: read_boundary, read_loads

contains

    subroutine read_boundary(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_values_t) :: v
        integer :: i, n1, n2, inc, k
        character(len=:), allocatable :: ctx
        allocate (model%fixed(2, model%mesh%nnode), source=.false.)
        allocate (model%prescribed(2, model%mesh%nnode), source=0.0_dp)
        do i = 1, group%n
            associate (card => group%cards(i))
                call get_range(file, card, boundary_fields, 'BOUNDARY', 'node', &
                               model%mesh%nnode, v, n1, n2, inc, error)
                if (allocated(error)) return
                ctx = 'BOUNDARY '//to_text(n1)
                do k = 1, 2
                    call read_card(file, card, boundary_fields, ctx, v, error, &
                                   only=[3 + k, 5 + k])
                    if (allocated(error)) return
                    if (v%given(5 + k) .and. v%int(3 + k) /= 1) then
                        call field_error(error, file, card, boundary_fields, 5 + k, ctx, &
                                         'blank: a prescribed value needs '// &
                                         trim(boundary_fields(3 + k)%name)//' = 1', &
                                         raw_text(card, boundary_fields, 5 + k))
                        return
                    end if
                end do
                if (v%int(4) == 0 .and. v%int(5) == 0) then
                    call card_error(error, file, card, 'BOUNDARY card fixes nothing: '// &
                                    'set IX and/or IY to 1')
                    return
                end if
                do k = 1, 2
                    if (v%int(3 + k) == 1) then
                        model%fixed(k, n1:n2:inc) = .true.
                        model%prescribed(k, n1:n2:inc) = v%x(5 + k)
                    end if
                end do
            end associate
        end do
    end subroutine read_boundary

    subroutine read_loads(file, group, model, set, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(in) :: model
        type(load_set_t), intent(out) :: set
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: keyword, name
        type(gravity_load_t) :: gravity
        type(pressure_load_t) :: pressure
        type(card_values_t) :: v
        integer :: i, n1, n2, inc, ngravity, npressure
        set%name = group%name
        allocate (set%nodal_force(2, model%mesh%nnode), source=0.0_dp)
        allocate (set%gravity(group%n), set%pressures(group%n))
        ngravity = 0
        npressure = 0
        do i = 1, group%n
            associate (card => group%cards(i))
                keyword = upper(raw_text(card, gravity_fields, 1))
                select case (keyword)
                case ('GRAVITY')
                    name = upper(raw_text(card, gravity_fields, 2))
                    gravity%group = all_groups
                    if (len(name) > 0 .and. name /= 'ALL') then
                        gravity%group = position(model%mesh%group_name, name)
                        if (gravity%group == 0) then
                            call field_error(error, file, card, gravity_fields, 2, 'GRAVITY', &
                                             'ALL or an element group ('// &
                                             group_list(model%mesh%group_name)//')', name)
                            return
                        end if
                    end if
                    call read_card(file, card, gravity_fields, 'GRAVITY', v, error, &
                                   only=[3, 4])
                    if (allocated(error)) return
                    gravity%ax = v%x(3)
                    gravity%ay = v%x(4)
                    ngravity = ngravity + 1
                    set%gravity(ngravity) = gravity
                case ('FORCE')
                    call get_range(file, card, force_fields, 'FORCE', 'node', &
                                   model%mesh%nnode, v, n1, n2, inc, error, offset=1)
                    if (allocated(error)) return
                    call read_card(file, card, force_fields, 'FORCE', v, error, only=[5, 6])
                    if (allocated(error)) return
                    set%nodal_force(1, n1:n2:inc) = set%nodal_force(1, n1:n2:inc) + v%x(5)
                    set%nodal_force(2, n1:n2:inc) = set%nodal_force(2, n1:n2:inc) + v%x(6)
                case ('PRESSURE')
                    call read_pressure(file, card, model, pressure, error)
                    if (allocated(error)) return
                    npressure = npressure + 1
                    set%pressures(npressure) = pressure
                case default
                    call card_error(error, file, card, "unknown load '"//keyword// &
                                    "' in LOADS: expected GRAVITY, FORCE or PRESSURE")
                    return
                end select
            end associate
        end do
        set%gravity = set%gravity(1:ngravity)
        set%pressures = set%pressures(1:npressure)
    end subroutine read_loads

    subroutine read_pressure(file, card, model, pressure, error)
        character(len=*), intent(in) :: file
        type(card_t), intent(in) :: card
        type(model_t), intent(in) :: model
        type(pressure_load_t), intent(out) :: pressure
        type(error_t), allocatable, intent(out) :: error
        type(card_values_t) :: v
        call read_card(file, card, pressure_fields, 'PRESSURE', v, error, only=[2])
        if (allocated(error)) return
        pressure%element = v%int(2)
        if (pressure%element < 1 .or. pressure%element > model%mesh%nelem) then
            call field_error(error, file, card, pressure_fields, 2, 'PRESSURE', &
                             'an element from 1 to '//to_text(model%mesh%nelem), &
                             raw_text(card, pressure_fields, 2))
            return
        end if
        if (is_joint_kind(model%mesh%kind(pressure%element))) then
            call field_error(error, file, card, pressure_fields, 2, 'PRESSURE', &
                             'a solid element (element '//to_text(pressure%element)// &
                             ' is a joint, which has no faces to load)', &
                             raw_text(card, pressure_fields, 2))
            return
        end if
        call read_card(file, card, pressure_fields, 'PRESSURE', v, error, only=[3])
        if (allocated(error)) return
        pressure%face = v%int(3)
        associate (conn => model%mesh%conn(:, pressure%element))
            if (pressure%face == 3 .and. conn(3) == conn(4)) then
                call field_error(error, file, card, pressure_fields, 3, 'PRESSURE', &
                                 'face 1, 2 or 4: element '//to_text(pressure%element)// &
                                 ' is a triangle, its face 3 has zero length', '3')
                return
            end if
        end associate
        call read_card(file, card, pressure_fields, 'PRESSURE', v, error, only=[4, 5])
        if (allocated(error)) return
        pressure%p1 = v%x(4)
        pressure%p2 = v%x(5)
    end subroutine read_pressure
end module cfrd_deck_loads
