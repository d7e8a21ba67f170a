!> RESERVOIR and GAUGES: the element faces the reservoir wets, and the named observation
!> points at nodes. The fields are read and checked against the card schema; here remain
!> the checks against the mesh and the names.
module cfrd_deck_reservoir
    use cfrd_error, only: error_t, fatal_error, input_error
    use cfrd_model, only: model_t, is_joint_kind
    use cfrd_cards, only: field_error, card_error, upper, to_text
    use cfrd_card_schema, only: reservoir_fields, gauge_fields
    use cfrd_card_reader, only: card_values_t, read_card, raw_text, position, group_list
    use cfrd_deck_groups, only: group_cards_t
    implicit none
    private

    public :: read_reservoir, read_gauges

contains

    !> RESERVOIR: the element faces the reservoir wets, each with the group whose placement
    !> covers it (blank: never covered).
    subroutine read_reservoir(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: name, ctx
        type(card_values_t) :: v
        integer :: i, j
        allocate (model%wet_faces(group%n))
        if (group%present .and. group%n == 0) then
            call fatal_error(error, file//':'//to_text(group%header_line)//': RESERVOIR '// &
                             'has no face cards', input_error)
            return
        end if
        do i = 1, group%n
            associate (card => group%cards(i), wet => model%wet_faces(i))
                call read_card(file, card, reservoir_fields, 'RESERVOIR', v, error, only=[1])
                if (allocated(error)) return
                wet%element = v%int(1)
                if (wet%element < 1 .or. wet%element > model%mesh%nelem) then
                    call field_error(error, file, card, reservoir_fields, 1, 'RESERVOIR', &
                                     'an element from 1 to '//to_text(model%mesh%nelem), &
                                     raw_text(card, reservoir_fields, 1))
                    return
                end if
                ctx = 'RESERVOIR '//to_text(wet%element)
                if (is_joint_kind(model%mesh%kind(wet%element))) then
                    call field_error(error, file, card, reservoir_fields, 1, 'RESERVOIR', &
                                     'a solid element (element '//to_text(wet%element)// &
                                     ' is a joint, which has no faces to wet)', &
                                     raw_text(card, reservoir_fields, 1))
                    return
                end if
                call read_card(file, card, reservoir_fields, ctx, v, error, only=[2, 3])
                if (allocated(error)) return
                wet%face = v%int(2)
                associate (conn => model%mesh%conn(:, wet%element))
                    if (wet%face == 3 .and. conn(3) == conn(4)) then
                        call field_error(error, file, card, reservoir_fields, 2, ctx, &
                                         'face 1, 2 or 4: element '//to_text(wet%element)// &
                                         ' is a triangle, its face 3 has zero length', '3')
                        return
                    end if
                end associate
                do j = 1, i - 1
                    if (model%wet_faces(j)%element == wet%element .and. &
                        model%wet_faces(j)%face == wet%face) then
                        call card_error(error, file, card, 'face '//to_text(wet%face)// &
                                        ' of element '//to_text(wet%element)// &
                                        ' is wetted twice (first at line '// &
                                        to_text(group%cards(j)%line)//')')
                        return
                    end if
                end do
                name = v%text(3)
                wet%cover = 0
                if (len(name) > 0) then
                    wet%cover = position(model%mesh%group_name, upper(name))
                    if (wet%cover == 0) then
                        call field_error(error, file, card, reservoir_fields, 3, ctx, &
                                         'blank or an element group ('// &
                                         group_list(model%mesh%group_name)//')', name)
                        return
                    end if
                end if
            end associate
        end do
    end subroutine read_reservoir

    !> GAUGES: named observation points at nodes.
    subroutine read_gauges(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_values_t) :: v
        integer :: i, j
        allocate (model%gauges(group%n))
        if (group%present .and. group%n == 0) then
            call fatal_error(error, file//':'//to_text(group%header_line)//': GAUGES has '// &
                             'no gauge cards', input_error)
            return
        end if
        do i = 1, group%n
            associate (card => group%cards(i), gauge => model%gauges(i))
                call read_card(file, card, gauge_fields, 'GAUGES', v, error, only=[1])
                if (allocated(error)) return
                gauge%node = v%int(1)
                if (gauge%node < 1 .or. gauge%node > model%mesh%nnode) then
                    call field_error(error, file, card, gauge_fields, 1, 'GAUGES', &
                                     'a node from 1 to '//to_text(model%mesh%nnode), &
                                     raw_text(card, gauge_fields, 1))
                    return
                end if
                call read_card(file, card, gauge_fields, 'GAUGES '//to_text(gauge%node), v, &
                               error, only=[2, 3])
                if (allocated(error)) return
                gauge%name = upper(v%text(2))
                do j = 1, i - 1
                    if (model%gauges(j)%name == gauge%name) then
                        call field_error(error, file, card, gauge_fields, 2, &
                                         'GAUGES '//to_text(gauge%node), &
                                         'a name not used before (line '// &
                                         to_text(group%cards(j)%line)//')', v%text(2))
                        return
                    end if
                end do
                gauge%label = v%text(3)
            end associate
        end do
    end subroutine read_gauges
end module cfrd_deck_reservoir
