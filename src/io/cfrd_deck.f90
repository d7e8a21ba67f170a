!> The deck reader: a card deck (docs/cards.md) in, a validated `model_t` out. Cards are
!> grouped under header cards; groups may come in any order and are processed in the order
!> their dependencies need (CONTROL, MATERIALS, NODES, ELEMENTS, BOUNDARY, LOADS). Each
!> group has its reader (cfrd_deck_*), which reads its cards against the card schema
!> (cfrd_card_schema). Every problem is an input error naming file, line, columns and field.
module cfrd_deck
    use cfrd_error, only: error_t, fatal_error, input_error
    use cfrd_model, only: model_t, is_joint_kind
    use cfrd_model_check, only: element_shape, first_unused_node, free_rigid_mode, &
                                shape_ok, shape_degenerate, unplaced_load
    use cfrd_cards, only: card_t, deck_lines_t, read_deck_lines, classify_line, card_error, &
                          upper, is_comment, to_text, get_text
    use cfrd_card_schema, only: title_fields, loads_header_fields
    use cfrd_card_reader, only: position
    use cfrd_deck_groups, only: group_cards_t, counts_t, append_card, leading_word, &
                                g_title, g_control, g_nodes, g_elements, g_materials, &
                                g_boundary, g_loads, g_stages, g_reservoir, g_gauges, &
                                g_interface, g_slab, g_contact, g_plinth, ngroups, group_keywords, &
                                valid_groups, group_required, load_keywords, stage_keywords, &
                                contact_keywords, effects_keyword, errctl_keyword, creep_keyword, &
                                wetting_keyword
    use cfrd_deck_control, only: read_control, apply_deck_effects
    use cfrd_deck_materials, only: read_materials
    use cfrd_deck_mesh, only: read_nodes, read_elements
    use cfrd_deck_interface, only: read_interface, read_slab, read_plinth
    use cfrd_deck_contact, only: read_contact
    use cfrd_deck_loads, only: read_boundary, read_loads
    use cfrd_deck_reservoir, only: read_reservoir, read_gauges
    use cfrd_deck_stages, only: read_stages
    implicit none
    private

    public :: read_deck, group_keywords

    !> At most this many named LOADS groups (load sets).
    integer, parameter :: max_load_sets = 1000

contains

    !> Read and validate the deck at `path` into `model`; with `text`, the deck is that
    !> text (a results file's /input/deck, cfrd --restart) and `path` names it in messages.
    subroutine read_deck(path, model, error, text)
        character(len=*), intent(in) :: path
        type(model_t), intent(out) :: model
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: text
        type(deck_lines_t) :: lines
        type(group_cards_t) :: groups(ngroups)
        type(group_cards_t), allocatable :: load_groups(:)
        type(counts_t) :: counts
        integer, allocatable :: node_line(:), element_line(:)
        integer :: i

        call read_deck_lines(path, lines, error, text)
        if (allocated(error)) return
        allocate (model%warnings(0))
        model%deck_file = path
        model%deck_text = lines%text
        model%title = ''
        model%units = 'KN-M'
        call sort_into_groups(lines, groups, load_groups, model%title, error)
        if (allocated(error)) return
        call read_control(path, groups(g_control), model, counts, error)
        if (allocated(error)) return
        call read_materials(path, groups(g_materials), counts, model, error)
        if (allocated(error)) return
        call read_nodes(path, groups(g_nodes), counts, model, node_line, error)
        if (allocated(error)) return
        call read_elements(path, groups(g_elements), counts, model, element_line, error)
        if (allocated(error)) return
        call read_interface(path, groups(g_interface), model, element_line, error)
        if (allocated(error)) return
        call read_slab(path, groups(g_slab), model, error)
        if (allocated(error)) return
        call read_contact(path, groups(g_contact), model, error)
        if (allocated(error)) return
        call read_boundary(path, groups(g_boundary), model, error)
        if (allocated(error)) return
        call read_plinth(path, groups(g_plinth), model, error)
        if (allocated(error)) return
        allocate (model%load_sets(size(load_groups)))
        do i = 1, size(load_groups)
            call read_loads(path, load_groups(i), model, model%load_sets(i), error)
            if (allocated(error)) return
        end do
        call read_reservoir(path, groups(g_reservoir), model, error)
        if (allocated(error)) return
        call read_gauges(path, groups(g_gauges), model, error)
        if (allocated(error)) return
        call read_stages(path, groups(g_stages), model, error)
        if (allocated(error)) return
        call check_model(path, groups, model, node_line, element_line, error)
        if (allocated(error)) return
        call apply_deck_effects(path, groups(g_control), model, error)
    end subroutine read_deck

    !> Split the deck into groups at header cards; stop at END or STOP.
    subroutine sort_into_groups(lines, groups, load_groups, title, error)
        type(deck_lines_t), intent(in) :: lines
        type(group_cards_t), intent(inout) :: groups(:)
        type(group_cards_t), allocatable, intent(out) :: load_groups(:)
        character(len=:), allocatable, intent(inout) :: title
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        character(len=:), allocatable :: text, word, name
        integer :: line, current, g, nsets, k
        logical :: ended
        current = 0
        ended = .false.
        ! Load set 1 is the unnamed default set, present even when the deck has no LOADS.
        allocate (load_groups(max_load_sets))
        nsets = 1
        load_groups(1)%present = .true.
        do line = 1, size(lines%first)
            text = lines%text(lines%first(line):lines%last(line))
            if (is_comment(text)) cycle
            call classify_line(lines%file, line, text, card, error)
            if (allocated(error)) return
            word = leading_word(card)
            if (len(word) > 0) then
                if (word == 'END' .or. word == 'STOP') then
                    ended = .true.
                    exit
                end if
                g = position(group_keywords, word)
                if (g == g_loads .and. .not. card%free) then
                    ! LOADS groups are load sets, told apart by the name in columns 11-20.
                    call get_text(card, loads_header_fields, 2, name)
                    name = upper(name)
                    k = 0
                    if (len(name) == 0) then
                        k = 1
                    else
                        do k = 2, nsets
                            if (load_groups(k)%name == name) exit
                        end do
                        if (k > nsets) k = 0
                    end if
                    if (k > 0) then
                        if (load_groups(k)%header_line > 0) then
                            call card_error(error, lines%file, card, 'duplicate group LOADS '// &
                                            name//' (first at line '// &
                                            to_text(load_groups(k)%header_line)// &
                                            '): each load set may appear once')
                            return
                        end if
                    else
                        if (nsets == max_load_sets) then
                            call card_error(error, lines%file, card, 'more than '// &
                                            to_text(max_load_sets)//' load sets')
                            return
                        end if
                        nsets = nsets + 1
                        k = nsets
                        load_groups(k)%name = name
                        load_groups(k)%present = .true.
                    end if
                    load_groups(k)%header_line = line
                    groups(g_loads)%present = .true.
                    current = -k
                    cycle
                end if
                if (g > 0 .and. .not. card%free) then
                    if (groups(g)%present) then
                        call card_error(error, lines%file, card, 'duplicate group '//word// &
                                        ' (first at line '//to_text(groups(g)%header_line)// &
                                        '): each group may appear once')
                        return
                    end if
                    groups(g)%present = .true.
                    groups(g)%header_line = line
                    current = g
                    if (g == g_title .and. len(text) > 10) &
                        call get_text(card, title_fields, 2, title)
                    cycle
                end if
                if (.not. ((current < 0 .and. any(load_keywords == word)) .or. &
                           (current == g_control .and. (word == effects_keyword .or. &
                                                        word == errctl_keyword)) .or. &
                           (current == g_materials .and. (word == creep_keyword .or. &
                                                          word == wetting_keyword)) .or. &
                           (current == g_stages .and. any(stage_keywords == word)) .or. &
                           (current == g_contact .and. any(contact_keywords == word)))) then
                    if (current < 0) then
                        call card_error(error, lines%file, card, "unknown load '"//word// &
                                        "' in LOADS: expected GRAVITY, FORCE or PRESSURE")
                    else if (current == g_stages) then
                        call card_error(error, lines%file, card, "unknown stage '"//word// &
                                        "' in STAGES: expected FILL, LOAD, RESET, WATER, "// &
                                        "WAIT or WET")
                    else if (current == g_contact) then
                        call card_error(error, lines%file, card, "unknown card '"//word// &
                                        "' in CONTACT: expected SURFACE or PAIR")
                    else if (current == g_control) then
                        call card_error(error, lines%file, card, "unknown card '"//word// &
                                        "' in CONTROL: expected EFFECTS, ERRCTL or the card of "// &
                                        "numbers")
                    else
                        call card_error(error, lines%file, card, "unknown group '"//word// &
                                        "': expected one of "//valid_groups)
                    end if
                    return
                end if
            end if
            if (current == 0) then
                call card_error(error, lines%file, card, 'data card before any group '// &
                                'header: a deck starts with a header card such as NODES')
                return
            end if
            if (current == g_title) then
                call card_error(error, lines%file, card, 'TITLE takes no data cards: '// &
                                'the title is columns 11-80 of the TITLE card')
                return
            end if
            if (current < 0) then
                call append_card(load_groups(-current), card)
            else
                call append_card(groups(current), card)
            end if
        end do
        load_groups = load_groups(1:nsets)
        if (.not. ended) then
            call fatal_error(error, lines%file//': no END card: is the deck truncated? '// &
                             '(a deck ends with END or STOP)', input_error)
            return
        end if
        do g = 1, ngroups
            if (group_required(g) .and. .not. groups(g)%present) then
                call fatal_error(error, lines%file//': missing group '// &
                                 trim(group_keywords(g))//' (required: NODES, ELEMENTS, '// &
                                 'MATERIALS, BOUNDARY)', input_error)
                return
            end if
        end do
    end subroutine sort_into_groups

    !> Model-level checks: element shapes, unused nodes, rigid-body modes.
    subroutine check_model(file, groups, model, node_line, element_line, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: groups(:)
        type(model_t), intent(in) :: model
        integer, intent(in) :: node_line(:), element_line(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: mode
        integer :: e, status, node, stage, what, item
        do e = 1, model%mesh%nelem
            if (is_joint_kind(model%mesh%kind(e))) cycle   ! zero thickness, checked by INTERFACE
            status = element_shape(model%mesh, e)
            if (status /= shape_ok) then
                if (status == shape_degenerate) then
                    call fatal_error(error, file//':'//to_text(element_line(e))// &
                                     ': element '//to_text(e)//' is degenerate (det J = 0 '// &
                                     'at a corner: zero area or collinear edges)', input_error)
                else
                    call fatal_error(error, file//':'//to_text(element_line(e))// &
                                     ': element '//to_text(e)//' is inverted (det J < 0: '// &
                                     'nodes clockwise or a re-entrant corner)', input_error)
                end if
                return
            end if
        end do
        node = first_unused_node(model%mesh)
        if (node > 0) then
            call fatal_error(error, file//':'//to_text(node_line(node))//': node '// &
                             to_text(node)//' is used by no element (it would have no '// &
                             'stiffness)', input_error)
            return
        end if
        call unplaced_load(model, stage, what, item)
        if (stage > 0) then
            call fatal_error(error, file//':'//to_text(model%stages(stage)%line)//': stage '// &
                             to_text(stage)//' ('//model%stages(stage)%label//'): '// &
                             trim(merge('PRESSURE on element', 'FORCE on node      ', &
                                        what == 1))//' '//to_text(item)//', which is not '// &
                             'placed yet (its FILL stage comes later)', input_error)
            return
        end if
        mode = free_rigid_mode(model)
        if (len(mode) > 0) then
            call fatal_error(error, file//':'//to_text(groups(g_boundary)%header_line)// &
                             ': rigid-body motion not suppressed: '//mode//' is free; '// &
                             'prescribe more displacements in BOUNDARY', input_error)
        end if
    end subroutine check_model
end module cfrd_deck
