!> The deck reader: a card deck (docs/cards.md) in, a validated `model_t` out. Cards are
!> grouped under header cards; groups may come in any order and are processed in the order
!> their dependencies need (CONTROL, MATERIALS, NODES, ELEMENTS, BOUNDARY, LOADS).
!> Every problem is an input error naming file, line, columns and field.
module cfrd_deck
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, input_error
    use cfrd_model, only: model_t, mesh_t, material_t, gravity_load_t, pressure_load_t, load_set_t, &
                          stage_t, stage_fill, stage_load, stage_reset, stage_water, stage_wait, &
                          wet_face_t, gauge_t, newtop_zero, &
                          newtop_count, solver_midpoint, solver_newton, &
                          plane_strain, axisymmetric, law_elastic, law_duncan_eb, law_goodman, &
                          elem_quad4, elem_quad4_shear, elem_joint_gauss, &
                          elem_joint_lobatto, is_joint_kind, &
                          interface_element_t, method_joint, method_thin, all_groups, &
                          contact_surface_t, contact_pair_t, scheme_mortar, scheme_nts, &
                          search_linear, search_rpim, effects_t, has_creep, &
                          has_wetting, stage_wet
    use cfrd_effects, only: apply_effects
    use cfrd_model_check, only: element_shape, first_unused_node, free_rigid_mode, &
                                shape_ok, shape_degenerate, unplaced_load, layer_thickness
    use cfrd_cards, only: card_t, field_t, deck_lines_t, int_field, real_field, text_field, &
                          read_deck_lines, classify_line, get_int, get_real, get_text, &
                          field_error, card_error, upper, is_comment, is_real, to_text
    use cfrd_strings, only: level_text
    use cfrd_deck_time, only: is_creep_card, read_creep_card, date_reader_t, &
                              is_wetting_card, read_wetting_card
    implicit none
    private

    public :: read_deck, group_keywords

    integer, parameter :: g_title = 1, g_control = 2, g_nodes = 3, g_elements = 4, &
                          g_materials = 5, g_boundary = 6, g_loads = 7, g_stages = 8, &
                          g_reservoir = 9, g_gauges = 10, g_interface = 11, g_slab = 12, &
                          g_contact = 13, ngroups = 13
    character(len=10), parameter :: group_keywords(ngroups) = [character(len=10) :: &
                                    'TITLE', 'CONTROL', 'NODES', 'ELEMENTS', 'MATERIALS', &
                                    'BOUNDARY', 'LOADS', 'STAGES', 'RESERVOIR', 'GAUGES', &
                                    'INTERFACE', 'SLAB', 'CONTACT']
    character(len=*), parameter :: valid_groups = 'TITLE, CONTROL, NODES, ELEMENTS, '// &
                                   'MATERIALS, BOUNDARY, LOADS, STAGES, RESERVOIR, GAUGES, '// &
                                   'INTERFACE, SLAB, CONTACT, END'
    logical, parameter :: group_required(ngroups) = [.false., .false., .true., .true., &
                                                     .true., .true., .false., .false., &
                                                     .false., .false., .false., .false., &
                                                     .false.]
    character(len=10), parameter :: load_keywords(3) = [character(len=10) :: 'GRAVITY', &
                                                        'FORCE', 'PRESSURE']
    character(len=10), parameter :: stage_keywords(6) = [character(len=10) :: 'FILL', &
                                                         'LOAD', 'RESET', 'WATER', 'WAIT', &
                                                         'WET']
    character(len=10), parameter :: contact_keywords(2) = [character(len=10) :: 'SURFACE', &
                                                           'PAIR']
    !> The card of CONTROL that lists the effects a deck asks for.
    character(len=*), parameter :: effects_keyword = 'EFFECTS'
    !> The card of MATERIALS that gives an EB material its creep (after its two cards).
    character(len=*), parameter :: creep_keyword = 'CREEP'
    !> ... and its wetting collapse (WETTING, after the two cards or the CREEP card).
    character(len=*), parameter :: wetting_keyword = 'WETTING'
    !> At most this many named LOADS groups (load sets).
    integer, parameter :: max_load_sets = 1000

    !> Largest node or element number accepted when the CONTROL card gives no count
    !> (guards against a mistyped number allocating gigabytes).
    integer, parameter :: max_number = 10000000

    !> Largest coordinate magnitude (m): larger is a mistyped field (a dam is kilometres
    !> wide; UTM northings stay below 1e7 m), and squares of lengths beyond 1e154 overflow.
    real(dp), parameter :: max_coordinate = 1.0e7_dp

    ! Card layouts (docs/cards.md): name, first column, width, kind.
    type(field_t), parameter :: control_fields(11) = [ &
                                field_t('NNODE', 1, 5, int_field), &
                                field_t('NELEM', 6, 5, int_field), &
                                field_t('NMAT', 11, 5, int_field), &
                                field_t('MODEL', 16, 5, int_field), &
                                field_t('PA', 21, 10, real_field), &
                                field_t('GAMMAW', 31, 10, real_field), &
                                field_t('UNITS', 41, 10, text_field), &
                                field_t('NEWTOP', 51, 5, int_field), &
                                field_t('SOLVER', 56, 5, int_field), &
                                field_t('TOL', 61, 10, real_field), &
                                field_t('MAXIT', 71, 5, int_field)]
    type(field_t), parameter :: effects_fields(9) = [ &
                                field_t('KEYWORD', 1, 10, text_field), &
                                field_t('ROCKFILL', 11, 10, text_field), &
                                field_t('UNLOAD', 21, 10, text_field), &
                                field_t('WATER', 31, 10, text_field), &
                                field_t('INTERFACE', 41, 10, text_field), &
                                field_t('FRICTION', 51, 10, text_field), &
                                field_t('SLIP', 61, 10, text_field), &
                                field_t('PHASES', 71, 10, text_field), &
                                field_t('CREEP', 81, 10, text_field)]
    type(field_t), parameter :: node_fields(7) = [ &
                                field_t('N1', 1, 5, int_field), &
                                field_t('N2', 6, 5, int_field), &
                                field_t('INC', 11, 5, int_field), &
                                field_t('X1', 16, 10, real_field), &
                                field_t('Y1', 26, 10, real_field), &
                                field_t('X2', 36, 10, real_field), &
                                field_t('Y2', 46, 10, real_field)]
    type(field_t), parameter :: element_fields(10) = [ &
                                field_t('NE', 1, 5, int_field), &
                                field_t('I', 6, 5, int_field), &
                                field_t('J', 11, 5, int_field), &
                                field_t('K', 16, 5, int_field), &
                                field_t('L', 21, 5, int_field), &
                                field_t('MAT', 26, 5, int_field), &
                                field_t('NGEN', 31, 5, int_field), &
                                field_t('NINC', 36, 5, int_field), &
                                field_t('GROUP', 41, 10, text_field), &
                                field_t('TYPE', 51, 10, text_field)]
    type(field_t), parameter :: material_fields(3) = [ &
                                field_t('M', 1, 5, int_field), &
                                field_t('LAW', 6, 10, text_field), &
                                field_t('LABEL', 16, 65, text_field)]
    type(field_t), parameter :: elastic_fields(3) = [ &
                                field_t('E', 1, 10, real_field), &
                                field_t('NU', 11, 10, real_field), &
                                field_t('GAMMA', 21, 10, real_field)]
    type(field_t), parameter :: eb_fields(7) = [ &
                                field_t('GAMMA', 1, 10, real_field), &
                                field_t('K', 11, 10, real_field), &
                                field_t('N', 21, 10, real_field), &
                                field_t('RF', 31, 10, real_field), &
                                field_t('KB', 41, 10, real_field), &
                                field_t('M', 51, 10, real_field), &
                                field_t('KUR', 61, 10, real_field)]
    type(field_t), parameter :: eb_strength_fields(4) = [ &
                                field_t('PHI0', 1, 10, real_field), &
                                field_t('DPHI', 11, 10, real_field), &
                                field_t('C', 21, 10, real_field), &
                                field_t('SIG3MIN', 31, 10, real_field)]
    type(field_t), parameter :: goodman_fields(8) = [ &
                                field_t('KNC', 1, 10, real_field), &
                                field_t('KNT', 11, 10, real_field), &
                                field_t('K1', 21, 10, real_field), &
                                field_t('N1', 31, 10, real_field), &
                                field_t('RF1', 41, 10, real_field), &
                                field_t('PHI', 51, 10, real_field), &
                                field_t('SNMIN', 61, 10, real_field), &
                                field_t('CUTOFF', 71, 5, int_field)]
    type(field_t), parameter :: interface_fields(10) = [ &
                                field_t('LINE', 1, 5, int_field), &
                                field_t('NB', 6, 5, int_field), &
                                field_t('NT', 11, 5, int_field), &
                                field_t('NGEN', 16, 5, int_field), &
                                field_t('INCB', 21, 5, int_field), &
                                field_t('INCT', 26, 5, int_field), &
                                field_t('MAT', 31, 5, int_field), &
                                field_t('TYPE', 36, 10, text_field), &
                                field_t('RULE', 46, 10, text_field), &
                                field_t('GROUP', 56, 10, text_field)]
    type(field_t), parameter :: slab_fields(1) = [field_t('GROUP', 11, 10, text_field)]
    type(field_t), parameter :: stage_fields(5) = [ &
                                field_t('KEYWORD', 1, 10, text_field), &
                                field_t('GROUP', 11, 10, text_field), &
                                field_t('NINC', 21, 5, int_field), &
                                field_t('DATE', 26, 10, text_field), &
                                field_t('LABEL', 36, 45, text_field)]
    !> A LOAD stage card: the same columns, field 2 naming a load set.
    type(field_t), parameter :: load_stage_fields(5) = [ &
                                field_t('KEYWORD', 1, 10, text_field), &
                                field_t('SET', 11, 10, text_field), &
                                field_t('NINC', 21, 5, int_field), &
                                field_t('DATE', 26, 10, text_field), &
                                field_t('LABEL', 36, 45, text_field)]
    !> A WATER stage card: field 2 is the reservoir level to reach.
    type(field_t), parameter :: water_stage_fields(5) = [ &
                                field_t('KEYWORD', 1, 10, text_field), &
                                field_t('LEVEL', 11, 10, real_field), &
                                field_t('NINC', 21, 5, int_field), &
                                field_t('DATE', 26, 10, text_field), &
                                field_t('LABEL', 36, 45, text_field)]
    type(field_t), parameter :: surface_fields(6) = [ &
                                field_t('KEYWORD', 1, 10, text_field), &
                                field_t('NAME', 11, 10, text_field), &
                                field_t('ELEM', 21, 5, int_field), &
                                field_t('FACE', 26, 5, int_field), &
                                field_t('NGEN', 31, 5, int_field), &
                                field_t('INC', 36, 5, int_field)]
    type(field_t), parameter :: pair_fields(8) = [ &
                                field_t('KEYWORD', 1, 10, text_field), &
                                field_t('SLAVE', 11, 10, text_field), &
                                field_t('MASTER', 21, 10, text_field), &
                                field_t('MU', 31, 10, real_field), &
                                field_t('TOL', 41, 10, real_field), &
                                field_t('SCHEME', 51, 10, text_field), &
                                field_t('SEARCH', 61, 10, text_field), &
                                field_t('CAST', 71, 5, int_field)]
    type(field_t), parameter :: reservoir_fields(3) = [ &
                                field_t('ELEM', 1, 5, int_field), &
                                field_t('FACE', 6, 5, int_field), &
                                field_t('COVER', 11, 10, text_field)]
    type(field_t), parameter :: gauge_fields(3) = [ &
                                field_t('NODE', 1, 5, int_field), &
                                field_t('NAME', 6, 10, text_field), &
                                field_t('LABEL', 16, 65, text_field)]
    type(field_t), parameter :: boundary_fields(7) = [ &
                                field_t('N1', 1, 5, int_field), &
                                field_t('N2', 6, 5, int_field), &
                                field_t('INC', 11, 5, int_field), &
                                field_t('IX', 16, 5, int_field), &
                                field_t('IY', 21, 5, int_field), &
                                field_t('UX', 26, 10, real_field), &
                                field_t('UY', 36, 10, real_field)]
    type(field_t), parameter :: gravity_fields(4) = [ &
                                field_t('KEYWORD', 1, 10, text_field), &
                                field_t('GROUP', 11, 10, text_field), &
                                field_t('AX', 21, 10, real_field), &
                                field_t('AY', 31, 10, real_field)]
    type(field_t), parameter :: force_fields(6) = [ &
                                field_t('KEYWORD', 1, 10, text_field), &
                                field_t('N1', 11, 5, int_field), &
                                field_t('N2', 16, 5, int_field), &
                                field_t('INC', 21, 5, int_field), &
                                field_t('FX', 26, 10, real_field), &
                                field_t('FY', 36, 10, real_field)]
    type(field_t), parameter :: pressure_fields(5) = [ &
                                field_t('KEYWORD', 1, 10, text_field), &
                                field_t('ELEM', 11, 5, int_field), &
                                field_t('FACE', 16, 5, int_field), &
                                field_t('P1', 21, 10, real_field), &
                                field_t('P2', 31, 10, real_field)]

    !> The cards of one group, in deck order.
    type :: group_cards_t
        character(len=10) :: name = ''     !! LOADS groups: the load set's name
        logical :: present = .false.
        integer :: header_line = 0
        integer :: n = 0
        type(card_t), allocatable :: cards(:)
    end type group_cards_t

    !> Counts announced on the CONTROL card (0 = not given) and where they stand.
    type :: counts_t
        integer :: nnode = 0, nelem = 0, nmat = 0
        integer :: line = 0
    end type counts_t

contains

    !> Read and validate the deck at `path` into `model`.
    subroutine read_deck(path, model, error)
        character(len=*), intent(in) :: path
        type(model_t), intent(out) :: model
        type(error_t), allocatable, intent(out) :: error
        type(deck_lines_t) :: lines
        type(group_cards_t) :: groups(ngroups)
        type(group_cards_t), allocatable :: load_groups(:)
        type(counts_t) :: counts
        integer, allocatable :: node_line(:), element_line(:)
        integer :: i

        call read_deck_lines(path, lines, error)
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
                    name = ''
                    if (len(text) > 10) name = upper(trim(adjustl(text(11:min(20, len(text))))))
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
                    if (g == g_title .and. len(text) > 10) title = trim(adjustl(text(11:)))
                    cycle
                end if
                if (.not. ((current < 0 .and. any(load_keywords == word)) .or. &
                           (current == g_control .and. word == effects_keyword) .or. &
                           (current == g_materials .and. (word == creep_keyword .or. &
                                                          word == wetting_keyword)) .or. &
                           (current == g_stages .and. any(stage_keywords == word)) .or. &
                           (current == g_contact .and. any(contact_keywords == word)))) then
                    if (current < 0) then
                        call card_error(error, lines%file, card, "unknown load '"//word// &
                                        "' in LOADS: expected GRAVITY, FORCE or PRESSURE")
                    else if (current == g_stages) then
                        call card_error(error, lines%file, card, "unknown stage '"//word// &
                                        "' in STAGES: expected FILL, LOAD, RESET, WATER, WAIT or WET")
                    else if (current == g_contact) then
                        call card_error(error, lines%file, card, "unknown card '"//word// &
                                        "' in CONTACT: expected SURFACE or PAIR")
                    else if (current == g_control) then
                        call card_error(error, lines%file, card, "unknown card '"//word// &
                                        "' in CONTROL: expected EFFECTS, or the card of "// &
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

    !> The upper-case word that starts a card (columns 1-10, or the first free token) when it
    !> starts with a letter; '' otherwise.
    function leading_word(card) result(word)
        type(card_t), intent(in) :: card
        character(len=:), allocatable :: word
        character(len=:), allocatable :: head
        if (card%free) then
            head = card%text(card%token_first(1):max(card%token_last(1), &
                                                     card%token_first(1) - 1))
        else
            head = card%text(1:min(10, len(card%text)))
        end if
        word = trim(adjustl(upper(head)))
        if (len(word) == 0) return
        if (index(word, ' ') > 0) word = word(1:index(word, ' ') - 1)
        if (.not. ((word(1:1) >= 'A' .and. word(1:1) <= 'Z'))) word = ''
        if (len(word) == 0 .or. card%free) return
        ! Headers are left-justified. An indented keyword is still taken as one, but any other
        ! indented word is data: '       inf' in an F10 field deserves a field error, not
        ! "unknown group 'INF'".
        if (card%text(1:1) == ' ' .and. .not. (word == 'END' .or. word == 'STOP' .or. &
            any(group_keywords == word) .or. any(load_keywords == word) .or. &
            any(stage_keywords == word) .or. any(contact_keywords == word) .or. &
            word == effects_keyword .or. word == creep_keyword .or. &
            word == wetting_keyword)) word = ''
    end function leading_word

    subroutine append_card(group, card)
        type(group_cards_t), intent(inout) :: group
        type(card_t), intent(in) :: card
        type(card_t), allocatable :: grown(:)
        if (.not. allocated(group%cards)) allocate (group%cards(64))
        if (group%n == size(group%cards)) then
            allocate (grown(2*group%n))
            grown(1:group%n) = group%cards(1:group%n)
            call move_alloc(grown, group%cards)
        end if
        group%n = group%n + 1
        group%cards(group%n) = card
    end subroutine append_card

    subroutine read_control(file, group, model, counts, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(counts_t), intent(out) :: counts
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: units
        character(len=*), parameter :: ctx = 'CONTROL'
        integer :: k, counts_read(3), i, numbers, effects
        ! No data card means all defaults (a blank card cannot be written: blank lines are
        ! skipped). The EFFECTS card may come before or after the card of numbers.
        numbers = 0
        effects = 0
        do i = 1, group%n
            if (leading_word(group%cards(i)) == effects_keyword) then
                if (effects > 0) then
                    call card_error(error, file, group%cards(i), 'CONTROL takes one '// &
                                    'EFFECTS card (the first is at line '// &
                                    to_text(group%cards(effects)%line)//')')
                    return
                end if
                effects = i
            else
                if (numbers > 0) then
                    call card_error(error, file, group%cards(i), 'CONTROL takes one card '// &
                                    'of numbers and one EFFECTS card (the card of numbers '// &
                                    'is at line '//to_text(group%cards(numbers)%line)//')')
                    return
                end if
                numbers = i
            end if
        end do
        if (effects > 0) then
            call read_effects(file, group%cards(effects), model%effects, error)
            if (allocated(error)) return
        end if
        if (numbers == 0) return
        associate (card => group%cards(numbers))
            counts%line = card%line
            call get_int(file, card, control_fields, 1, ctx, 0, counts%nnode, error)
            if (allocated(error)) return
            call get_int(file, card, control_fields, 2, ctx, 0, counts%nelem, error)
            if (allocated(error)) return
            call get_int(file, card, control_fields, 3, ctx, 0, counts%nmat, error)
            if (allocated(error)) return
            counts_read = [counts%nnode, counts%nelem, counts%nmat]
            do k = 1, 3
                if (counts_read(k) < 0) then
                    call field_error(error, file, card, control_fields, k, ctx, &
                                     'a count >= 1 (or blank)', to_text(counts_read(k)))
                    return
                end if
            end do
            call get_int(file, card, control_fields, 4, ctx, plane_strain, model%analysis, &
                         error)
            if (allocated(error)) return
            if (model%analysis /= plane_strain .and. model%analysis /= axisymmetric) then
                call field_error(error, file, card, control_fields, 4, ctx, &
                                 '1 (plane strain) or 2 (axisymmetric)', &
                                 to_text(model%analysis))
                return
            end if
            call get_positive(file, card, control_fields, 5, ctx, 101.325_dp, model%pa, error)
            if (allocated(error)) return
            call get_positive(file, card, control_fields, 6, ctx, 9.81_dp, model%gamma_w, error)
            if (allocated(error)) return
            call get_text(card, control_fields, 7, units)
            if (len(units) > 0 .and. upper(units) /= 'KN-M') then
                call field_error(error, file, card, control_fields, 7, ctx, &
                                 'KN-M (m, kN, kPa) or blank', units)
                return
            end if
            call get_int(file, card, control_fields, 8, ctx, newtop_zero, model%newtop, error)
            if (allocated(error)) return
            if (model%newtop /= newtop_zero .and. model%newtop /= newtop_count) then
                call field_error(error, file, card, control_fields, 8, ctx, &
                                 '0 (zero a new layer''s displacements when it is complete) '// &
                                 'or 1 (count them)', to_text(model%newtop))
                return
            end if
            call get_int(file, card, control_fields, 9, ctx, solver_midpoint, model%solver, error)
            if (allocated(error)) return
            if (model%solver < solver_midpoint .or. model%solver > solver_newton) then
                call field_error(error, file, card, control_fields, 9, ctx, &
                                 '1 (midpoint), 2 (forward Euler) or 3 (Newton)', &
                                 to_text(model%solver))
                return
            end if
            call get_positive(file, card, control_fields, 10, ctx, 1.0e-6_dp, model%tolerance, &
                              error)
            if (allocated(error)) return
            call get_int(file, card, control_fields, 11, ctx, 20, model%max_iterations, error)
            if (allocated(error)) return
            if (model%max_iterations < 1) then
                call field_error(error, file, card, control_fields, 11, ctx, &
                                 'a number of iterations >= 1', to_text(model%max_iterations))
                return
            end if
        end associate
    end subroutine read_control

    !> The EFFECTS card: each field a keyword, blank for the default (the effect on).
    subroutine read_effects(file, card, effects, error)
        character(len=*), intent(in) :: file
        type(card_t), intent(in) :: card
        type(effects_t), intent(out) :: effects
        type(error_t), allocatable, intent(out) :: error
        effects%line = card%line
        call choose(2, 'NONLINEAR', 'LINEAR', effects%nonlinear_rockfill)
        if (allocated(error)) return
        call choose(3, 'ON', 'OFF', effects%unload)
        if (allocated(error)) return
        call choose(4, 'ON', 'OFF', effects%water)
        if (allocated(error)) return
        call choose(5, 'DECK', 'BONDED', effects%interface)
        if (allocated(error)) return
        call choose(6, 'ON', 'OFF', effects%friction)
        if (allocated(error)) return
        call choose(7, 'LARGE', 'SMALL', effects%large_slip)
        if (allocated(error)) return
        call choose(8, 'ON', 'OFF', effects%phases)
        if (allocated(error)) return
        call choose(9, 'ON', 'OFF', effects%creep)
    contains
        !> Field k: blank or `on_word` sets `on`, `off_word` clears it.
        subroutine choose(k, on_word, off_word, on)
            integer, intent(in) :: k
            character(len=*), intent(in) :: on_word, off_word
            logical, intent(out) :: on
            character(len=:), allocatable :: word
            call get_text(card, effects_fields, k, word)
            word = upper(word)
            on = .true.
            if (len(word) == 0 .or. word == on_word) return
            if (word == off_word) then
                on = .false.
                return
            end if
            call field_error(error, file, card, effects_fields, k, 'CONTROL EFFECTS', &
                             on_word//' (the default, also blank) or '//off_word, word)
        end subroutine choose
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

    subroutine read_materials(file, group, counts, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(counts_t), intent(in) :: counts
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: number(:), first_card(:), defined(:)
        type(material_t), allocatable :: mats(:)
        character(len=:), allocatable :: law, label, ctx
        integer :: i, n, m, limit, nmat
        real(dp) :: value
        allocate (number(group%n), first_card(group%n), mats(group%n))
        n = 0
        i = 1
        limit = merge(counts%nmat, group%n, counts%nmat > 0)
        do while (i <= group%n)
            associate (card => group%cards(i))
                if (is_creep_card(card) .or. is_wetting_card(card)) then
                    law = trim(merge('CREEP  ', 'WETTING', is_creep_card(card)))
                    ctx = 'a '//law//' card follows the two parameter cards of an EB material'
                    if (law == 'WETTING') ctx = ctx//' or its CREEP card'
                    if (n > 0) then
                        if (mats(n)%law /= law_duncan_eb) then
                            ctx = ctx//' (MATERIALS '//to_text(number(n))//' is not EB)'
                        else if ((law == 'CREEP' .and. mats(n)%creep) .or. &
                                 (law == 'WETTING' .and. mats(n)%wetting)) then
                            ctx = ctx//' (MATERIALS '//to_text(number(n))//' has one already)'
                        else
                            ctx = ctx//' (MATERIALS '//to_text(number(n))//': CREEP '// &
                                  'before WETTING)'
                        end if
                    end if
                    call card_error(error, file, card, ctx)
                    return
                end if
                call get_int(file, card, material_fields, 1, 'MATERIALS', 0, m, error)
                if (allocated(error)) return
                ctx = 'MATERIALS '//to_text(m)
                if (m < 1 .or. m > limit) then
                    call field_error(error, file, card, material_fields, 1, 'MATERIALS', &
                                     'a material number from 1 to '//to_text(limit), &
                                     to_text(m))
                    return
                end if
                call get_text(card, material_fields, 2, law)
                law = upper(law)
                if (law /= 'ELASTIC' .and. law /= 'EB' .and. law /= 'GOODMAN') then
                    call field_error(error, file, card, material_fields, 2, ctx, &
                                     'a material law: ELASTIC, EB or GOODMAN', law)
                    return
                end if
                call get_text(card, material_fields, 3, label)
                n = n + 1
                number(n) = m
                first_card(n) = i
                select case (law)
                case ('ELASTIC')
                    mats(n)%law = law_elastic
                case ('EB')
                    mats(n)%law = law_duncan_eb
                case default
                    mats(n)%law = law_goodman
                end select
                mats(n)%label = label
            end associate
            if (mats(n)%law == law_duncan_eb) then
                call read_eb_cards(file, group, i, m, model%pa, mats(n), error)
                if (allocated(error)) return
                i = i + 3
                if (i <= group%n) then
                    if (is_creep_card(group%cards(i))) then
                        call read_creep_card(file, group%cards(i), m, mats(n), error)
                        if (allocated(error)) return
                        i = i + 1
                    end if
                end if
                if (i <= group%n) then
                    if (is_wetting_card(group%cards(i))) then
                        call read_wetting_card(file, group%cards(i), m, mats(n), error)
                        if (allocated(error)) return
                        i = i + 1
                    end if
                end if
                cycle
            end if
            if (mats(n)%law == law_goodman) then
                call read_goodman_card(file, group, i, m, model, mats(n), error)
                if (allocated(error)) return
                i = i + 2
                cycle
            end if
            if (i == group%n) then
                call card_error(error, file, group%cards(i), 'MATERIALS '//to_text(m)// &
                                ': missing parameter card (E, NU, GAMMA) after this card')
                return
            end if
            if (is_material_card(group%cards(i + 1))) then
                call card_error(error, file, group%cards(i + 1), 'MATERIALS '//to_text(m)// &
                                ': missing parameter card (E, NU, GAMMA) before this card')
                return
            end if
            associate (card => group%cards(i + 1))
                call get_real(file, card, elastic_fields, 1, ctx, 0.0_dp, value, error)
                if (allocated(error)) return
                if (.not. value > 0.0_dp) then
                    call field_error(error, file, card, elastic_fields, 1, ctx, &
                                     'a real > 0 (kPa)', real_text(card, elastic_fields, 1))
                    return
                end if
                mats(n)%youngs_modulus = value
                call get_real(file, card, elastic_fields, 2, ctx, -1.0_dp, value, error)
                if (allocated(error)) return
                if (.not. (value >= 0.0_dp .and. value < 0.5_dp)) then
                    call field_error(error, file, card, elastic_fields, 2, ctx, &
                                     'a real with 0 <= NU < 0.5', &
                                     real_text(card, elastic_fields, 2))
                    return
                end if
                mats(n)%poisson_ratio = value
                call get_real(file, card, elastic_fields, 3, ctx, 0.0_dp, value, error)
                if (allocated(error)) return
                if (value < 0.0_dp) then
                    call field_error(error, file, card, elastic_fields, 3, ctx, &
                                     'a real >= 0 (kN/m3)', real_text(card, elastic_fields, 3))
                    return
                end if
                mats(n)%unit_weight = value
            end associate
            i = i + 2
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
    end subroutine read_materials

    !> The two parameter cards of an E-B material after its card 1 at group%cards(i).
    subroutine read_eb_cards(file, group, i, m, pa, mat, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        integer, intent(in) :: i, m
        real(dp), intent(in) :: pa
        type(material_t), intent(inout) :: mat
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: ctx
        logical :: given
        integer :: k
        ctx = 'MATERIALS '//to_text(m)
        do k = 1, 2
            if (i + k > group%n) then
                call card_error(error, file, group%cards(i + k - 1), ctx//': missing '// &
                                'parameter card '//to_text(k + 1)//' of law EB after this card')
                return
            end if
            if (is_material_card(group%cards(i + k))) then
                call card_error(error, file, group%cards(i + k), ctx//': missing '// &
                                'parameter card '//to_text(k + 1)//' of law EB before this card')
                return
            end if
        end do
        associate (card => group%cards(i + 1))
            call get_eb_bounded(card, eb_fields, 1, .false., 0.0_dp, 0.0_dp, huge(1.0_dp), &
                             'a real >= 0 (kN/m3)', mat%unit_weight)
            if (allocated(error)) return
            call get_eb_bounded(card, eb_fields, 2, .true., 0.0_dp, tiny(1.0_dp), huge(1.0_dp), &
                             'a real > 0', mat%k_modulus)
            if (allocated(error)) return
            call get_eb_bounded(card, eb_fields, 3, .true., 0.0_dp, 0.0_dp, 0.999_dp, &
                             'a real with 0 <= N < 1', mat%n_exponent)
            if (allocated(error)) return
            call get_eb_bounded(card, eb_fields, 4, .true., 0.0_dp, tiny(1.0_dp), 1.0_dp, &
                             'a real with 0 < RF <= 1', mat%failure_ratio)
            if (allocated(error)) return
            call get_eb_bounded(card, eb_fields, 5, .true., 0.0_dp, tiny(1.0_dp), huge(1.0_dp), &
                             'a real > 0', mat%k_bulk)
            if (allocated(error)) return
            call get_eb_bounded(card, eb_fields, 6, .true., 0.0_dp, -0.999_dp, 0.999_dp, &
                             'a real with -1 < M < 1', mat%m_exponent)
            if (allocated(error)) return
            ! Kur blank: 2 K, a common rockfill value (reference file, [choice]).
            call get_eb_bounded(card, eb_fields, 7, .false., 2.0_dp*mat%k_modulus, tiny(1.0_dp), &
                             huge(1.0_dp), 'a real > 0 (blank = 2 K)', mat%k_unload)
            if (allocated(error)) return
        end associate
        associate (card => group%cards(i + 2))
            call get_eb_bounded(card, eb_strength_fields, 1, .true., 0.0_dp, tiny(1.0_dp), &
                             89.0_dp, 'an angle in degrees, 0 < PHI0 < 90', mat%phi0)
            if (allocated(error)) return
            call get_eb_bounded(card, eb_strength_fields, 2, .false., 0.0_dp, 0.0_dp, 89.0_dp, &
                             'an angle in degrees >= 0', mat%dphi)
            if (allocated(error)) return
            call get_eb_bounded(card, eb_strength_fields, 3, .false., 0.0_dp, 0.0_dp, &
                             huge(1.0_dp), 'a real >= 0 (kPa)', mat%cohesion)
            if (allocated(error)) return
            ! Floor on sigma3 for the moduli, blank: 0.1 pa (docs/theory.md section 8).
            call get_eb_bounded(card, eb_strength_fields, 4, .false., 0.1_dp*pa, tiny(1.0_dp), &
                             huge(1.0_dp), 'a real > 0 (kPa, blank = 0.1 PA)', mat%sigma3_floor)
        end associate
    contains
        !> Real field k of `card`: required or `default` when blank; must lie in [lo, hi].
        subroutine get_eb_bounded(card, fields, k, required, default, lo, hi, expected, value)
            type(card_t), intent(in) :: card
            type(field_t), intent(in) :: fields(:)
            integer, intent(in) :: k
            logical, intent(in) :: required
            real(dp), intent(in) :: default, lo, hi
            character(len=*), intent(in) :: expected
            real(dp), intent(out) :: value
            call get_real(file, card, fields, k, ctx, default, value, error, given)
            if (allocated(error)) return
            if (required .and. .not. given) then
                call field_error(error, file, card, fields, k, ctx, expected, '')
            else if (.not. (value >= lo .and. value <= hi)) then
                call field_error(error, file, card, fields, k, ctx, expected, &
                                 raw_text(card, fields, k))
            end if
        end subroutine get_eb_bounded
    end subroutine read_eb_cards

    !> The parameter card of a Goodman joint material after its card 1 at group%cards(i).
    subroutine read_goodman_card(file, group, i, m, model, mat, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        integer, intent(in) :: i, m
        type(model_t), intent(in) :: model
        type(material_t), intent(inout) :: mat
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: ctx
        integer :: cutoff
        ctx = 'MATERIALS '//to_text(m)
        if (i == group%n) then
            call card_error(error, file, group%cards(i), ctx//': missing parameter card '// &
                            '(KNC, KNT, K1, N1, RF1, PHI, SNMIN, CUTOFF) after this card')
            return
        end if
        if (is_material_card(group%cards(i + 1))) then
            call card_error(error, file, group%cards(i + 1), ctx//': missing parameter '// &
                            'card (KNC, KNT, K1, N1, RF1, PHI, SNMIN, CUTOFF) before this card')
            return
        end if
        associate (card => group%cards(i + 1))
            call get_bounded(file, card, goodman_fields, 1, ctx, .true., 0.0_dp, &
                             tiny(1.0_dp), huge(1.0_dp), 'a real > 0 (kPa/m)', &
                             mat%kn_compression, error)
            if (allocated(error)) return
            call get_bounded(file, card, goodman_fields, 2, ctx, .true., 0.0_dp, &
                             tiny(1.0_dp), huge(1.0_dp), 'a real > 0 (kPa/m)', &
                             mat%kn_tension, error)
            if (allocated(error)) return
            call get_bounded(file, card, goodman_fields, 3, ctx, .true., 0.0_dp, &
                             tiny(1.0_dp), huge(1.0_dp), 'a real > 0', mat%k1, error)
            if (allocated(error)) return
            call get_bounded(file, card, goodman_fields, 4, ctx, .true., 0.0_dp, 0.0_dp, &
                             0.999_dp, 'a real with 0 <= N1 < 1', mat%n1, error)
            if (allocated(error)) return
            call get_bounded(file, card, goodman_fields, 5, ctx, .true., 0.0_dp, 0.0_dp, &
                             1.0_dp, 'a real with 0 <= RF1 <= 1', mat%rf1, error)
            if (allocated(error)) return
            call get_bounded(file, card, goodman_fields, 6, ctx, .true., 0.0_dp, &
                             tiny(1.0_dp), 89.0_dp, 'an angle in degrees, 0 < PHI < 90', &
                             mat%phi, error)
            if (allocated(error)) return
            ! Floor on the compressive normal stress in ks, blank: 0.1 pa, as SIG3MIN of EB.
            call get_bounded(file, card, goodman_fields, 7, ctx, .false., 0.1_dp*model%pa, &
                             tiny(1.0_dp), huge(1.0_dp), 'a real > 0 (kPa, blank = 0.1 PA)', &
                             mat%sigma_n_floor, error)
            if (allocated(error)) return
            call get_int(file, card, goodman_fields, 8, ctx, 0, cutoff, error)
            if (allocated(error)) return
            if (cutoff /= 0 .and. cutoff /= 1) then
                call field_error(error, file, card, goodman_fields, 8, ctx, &
                                 '0 (tension carried with KNT) or 1 (tension cut-off)', &
                                 to_text(cutoff))
                return
            end if
            mat%tension_cutoff = cutoff == 1
            mat%gamma_w = model%gamma_w
        end associate
    end subroutine read_goodman_card

    !> Real field k of `card`: required or `default` when blank; must lie in [lo, hi].
    subroutine get_bounded(file, card, fields, k, ctx, required, default, lo, hi, expected, &
                           value, error)
        character(len=*), intent(in) :: file, ctx
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        logical, intent(in) :: required
        real(dp), intent(in) :: default, lo, hi
        character(len=*), intent(in) :: expected
        real(dp), intent(out) :: value
        type(error_t), allocatable, intent(out) :: error
        logical :: given
        call get_real(file, card, fields, k, ctx, default, value, error, given)
        if (allocated(error)) return
        if (required .and. .not. given) then
            call field_error(error, file, card, fields, k, ctx, expected, '')
        else if (.not. (value >= lo .and. value <= hi)) then
            call field_error(error, file, card, fields, k, ctx, expected, &
                             raw_text(card, fields, k))
        end if
    end subroutine get_bounded

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

    subroutine read_nodes(file, group, counts, model, node_line, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(counts_t), intent(in) :: counts
        type(model_t), intent(inout) :: model
        integer, allocatable, intent(out) :: node_line(:)
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: n1(:), n2(:), inc(:)
        real(dp), allocatable :: p1(:, :), p2(:, :)
        real(dp) :: xy(4)
        integer :: i, k, steps, node, limit, nnode
        logical :: given_x2, given_y2
        character(len=:), allocatable :: ctx
        allocate (n1(group%n), n2(group%n), inc(group%n), p1(2, group%n), p2(2, group%n))
        limit = merge(counts%nnode, max_number, counts%nnode > 0)
        do i = 1, group%n
            associate (card => group%cards(i))
                call get_range(file, card, node_fields, 'NODES', 'node', limit, &
                               n1(i), n2(i), inc(i), error)
                if (allocated(error)) return
                ctx = 'NODES '//to_text(n1(i))
                call get_real(file, card, node_fields, 4, ctx, 0.0_dp, p1(1, i), error)
                if (allocated(error)) return
                call get_real(file, card, node_fields, 5, ctx, 0.0_dp, p1(2, i), error)
                if (allocated(error)) return
                call get_real(file, card, node_fields, 6, ctx, 0.0_dp, p2(1, i), error, &
                              given_x2)
                if (allocated(error)) return
                call get_real(file, card, node_fields, 7, ctx, 0.0_dp, p2(2, i), error, &
                              given_y2)
                if (allocated(error)) return
                xy = [p1(:, i), p2(:, i)]
                do k = 1, 4
                    if (abs(xy(k)) > max_coordinate) then
                        call field_error(error, file, card, node_fields, k + 3, ctx, &
                                         'a coordinate of magnitude at most 1e7 (m)', &
                                         raw_text(card, node_fields, k + 3))
                        return
                    end if
                end do
                if (n2(i) > n1(i) .and. .not. (given_x2 .and. given_y2)) then
                    k = merge(7, 6, given_x2)
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

    !> Fields N1, N2, INC (the first three of `fields`) of a node-range card, checked:
    !> 1 <= N1 <= N2 <= limit, INC > 0 dividing N2 - N1.
    subroutine get_range(file, card, fields, group_name, what, limit, n1, n2, inc, error, &
                         offset)
        character(len=*), intent(in) :: file, group_name, what
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: limit
        integer, intent(out) :: n1, n2, inc
        type(error_t), allocatable, intent(out) :: error
        integer, intent(in), optional :: offset
        integer :: f
        f = 0
        if (present(offset)) f = offset
        call get_int(file, card, fields, f + 1, group_name, 0, n1, error)
        if (allocated(error)) return
        if (n1 < 1 .or. n1 > limit) then
            call field_error(error, file, card, fields, f + 1, group_name, &
                             'a '//what//' number from 1 to '//to_text(limit), &
                             raw_text(card, fields, f + 1))
            return
        end if
        call get_int(file, card, fields, f + 2, group_name, n1, n2, error)
        if (allocated(error)) return
        if (n2 < n1 .or. n2 > limit) then
            call field_error(error, file, card, fields, f + 2, group_name, &
                             'a last '//what//' from N1 = '//to_text(n1)//' to '// &
                             to_text(limit), raw_text(card, fields, f + 2))
            return
        end if
        call get_int(file, card, fields, f + 3, group_name, 1, inc, error)
        if (allocated(error)) return
        if (inc < 1) then
            call field_error(error, file, card, fields, f + 3, group_name, &
                             'an increment >= 1', raw_text(card, fields, f + 3))
            return
        end if
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
        integer :: i, k, g, e, limit, nelem, nnode, a, b
        allocate (first(group%n), nodes(4, group%n), mat(group%n), ngen(group%n), &
                  ninc(group%n), grp(group%n), kinds(group%n), names(0))
        limit = merge(counts%nelem, max_number, counts%nelem > 0)
        nnode = model%mesh%nnode
        do i = 1, group%n
            associate (card => group%cards(i))
                call get_int(file, card, element_fields, 1, 'ELEMENTS', 0, first(i), error)
                if (allocated(error)) return
                if (first(i) < 1 .or. first(i) > limit) then
                    call field_error(error, file, card, element_fields, 1, 'ELEMENTS', &
                                     'an element number from 1 to '//to_text(limit), &
                                     raw_text(card, element_fields, 1))
                    return
                end if
                ctx = 'ELEMENTS '//to_text(first(i))
                call get_int(file, card, element_fields, 7, ctx, 0, ngen(i), error)
                if (allocated(error)) return
                if (ngen(i) < 0 .or. first(i) + ngen(i) > limit) then
                    call field_error(error, file, card, element_fields, 7, ctx, &
                                     'a count from 0 to '//to_text(limit - first(i)), &
                                     raw_text(card, element_fields, 7))
                    return
                end if
                call get_int(file, card, element_fields, 8, ctx, 1, ninc(i), error)
                if (allocated(error)) return
                do k = 1, 4
                    call get_int(file, card, element_fields, k + 1, ctx, 0, nodes(k, i), &
                                 error)
                    if (allocated(error)) return
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
                call get_int(file, card, element_fields, 6, ctx, 0, mat(i), error)
                if (allocated(error)) return
                if (mat(i) < 1 .or. mat(i) > size(model%materials)) then
                    call field_error(error, file, card, element_fields, 6, ctx, &
                                     'a material number from 1 to '// &
                                     to_text(size(model%materials)), &
                                     raw_text(card, element_fields, 6))
                    return
                end if
                if (model%materials(mat(i))%law == law_goodman) then
                    call field_error(error, file, card, element_fields, 6, ctx, &
                                     'a solid material: GOODMAN is the law of joints, '// &
                                     'given on INTERFACE cards', raw_text(card, element_fields, 6))
                    return
                end if
                call get_text(card, element_fields, 10, name)
                select case (upper(name))
                case ('', 'Q4')
                    kinds(i) = elem_quad4
                case ('Q4S')
                    kinds(i) = elem_quad4_shear
                case default
                    call field_error(error, file, card, element_fields, 10, ctx, &
                                     'an element type: Q4 (blank) or Q4S (assumed shear '// &
                                     'strain, for slabs in bending)', name)
                    return
                end select
                call get_text(card, element_fields, 9, name)
                name = upper(name)
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
                                lines(:), new_conn(:, :)
        character(len=:), allocatable :: ctx, text
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
                call get_int(file, card, interface_fields, 1, 'INTERFACE', 0, line, error)
                if (allocated(error)) return
                if (line < 1) then
                    call field_error(error, file, card, interface_fields, 1, 'INTERFACE', &
                                     'an interface line number >= 1', &
                                     raw_text(card, interface_fields, 1))
                    return
                end if
                ctx = 'INTERFACE line '//to_text(line)
                call get_int(file, card, interface_fields, 4, ctx, 0, ngen, error)
                if (allocated(error)) return
                if (ngen < 0) then
                    call field_error(error, file, card, interface_fields, 4, ctx, &
                                     'a count >= 0', raw_text(card, interface_fields, 4))
                    return
                end if
                call get_int(file, card, interface_fields, 5, ctx, 1, incb, error)
                if (allocated(error)) return
                call get_int(file, card, interface_fields, 6, ctx, 1, inct, error)
                if (allocated(error)) return
                do k = 2, 3
                    call get_int(file, card, interface_fields, k, ctx, 0, nb, error)
                    if (allocated(error)) return
                    a = nb
                    b = nb + ngen*merge(incb, inct, k == 2)
                    if (min(a, b) < 1 .or. max(a, b) > model%mesh%nnode) then
                        call field_error(error, file, card, interface_fields, k, ctx, &
                                         'a node from 1 to '//to_text(model%mesh%nnode)// &
                                         trim(merge(' for every generated pair', &
                                                    '                         ', ngen > 0)), &
                                         raw_text(card, interface_fields, k))
                        return
                    end if
                end do
                call get_int(file, card, interface_fields, 2, ctx, 0, nb, error)
                call get_int(file, card, interface_fields, 3, ctx, 0, nt, error)
                if (nb == nt .or. (ngen > 0 .and. (incb == 0 .or. inct == 0))) then
                    call card_error(error, file, card, ctx//': the bottom and top nodes of '// &
                                    'a pair must differ, and INCB, INCT must not be 0')
                    return
                end if
                call get_int(file, card, interface_fields, 7, ctx, 0, card_mat(i), error)
                if (allocated(error)) return
                if (card_mat(i) < 1 .or. card_mat(i) > size(model%materials)) then
                    call field_error(error, file, card, interface_fields, 7, ctx, &
                                     'a material number from 1 to '// &
                                     to_text(size(model%materials)), &
                                     raw_text(card, interface_fields, 7))
                    return
                end if
                call get_text(card, interface_fields, 8, text)
                text = upper(text)
                select case (text)
                case ('JOINT')
                    card_method(i) = method_joint
                case ('THIN')
                    card_method(i) = method_thin
                case default
                    call field_error(error, file, card, interface_fields, 8, ctx, &
                                     'an interface type: JOINT or THIN', text)
                    return
                end select
                if ((model%materials(card_mat(i))%law == law_goodman) .neqv. &
                    (card_method(i) == method_joint)) then
                    call field_error(error, file, card, interface_fields, 7, ctx, &
                                     trim(merge('a GOODMAN material for a JOINT         ', &
                                                'a solid material (not GOODMAN) for THIN', &
                                                card_method(i) == method_joint)), &
                                     raw_text(card, interface_fields, 7))
                    return
                end if
                call get_text(card, interface_fields, 9, text)
                text = upper(text)
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
                call get_text(card, interface_fields, 10, text)
                text = upper(text)
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
        allocate (new_conn(4, 0))
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
                    gap = max(norm2(x(:, conn(4)) - x(:, conn(1))), &
                              norm2(x(:, conn(3)) - x(:, conn(2))))
                    if (gap > 1.0e-6_dp*length) then
                        call fatal_error(error, file//':'//to_text(element_line(e))//': '// &
                                         ctx//': the nodes of a pair are '// &
                                         trim(real_text_of(gap))//' m apart; a JOINT has '// &
                                         'zero thickness (use THIN for a layer)', input_error)
                        return
                    end if
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
        character(len=:), allocatable :: name
        integer :: i, g
        allocate (model%slab_groups(0))
        if (group%present .and. group%n == 0) then
            call fatal_error(error, file//':'//to_text(group%header_line)//': SLAB has no '// &
                             'group cards', input_error)
            return
        end if
        do i = 1, group%n
            associate (card => group%cards(i))
                call get_text(card, slab_fields, 1, name)
                g = position(model%mesh%group_name, upper(name))
                if (g == 0) then
                    call field_error(error, file, card, slab_fields, 1, 'SLAB', &
                                     'an element group ('//group_list(model%mesh%group_name)// &
                                     ')', name)
                    return
                end if
                if (any(model%slab_groups == g)) then
                    call field_error(error, file, card, slab_fields, 1, 'SLAB', &
                                     'a group not listed before', name)
                    return
                end if
                model%slab_groups = [model%slab_groups, g]
            end associate
        end do
    end subroutine read_slab

    subroutine read_boundary(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        integer :: i, n1, n2, inc, code(2), k
        real(dp) :: value(2)
        logical :: given(2)
        character(len=:), allocatable :: ctx
        allocate (model%fixed(2, model%mesh%nnode), source=.false.)
        allocate (model%prescribed(2, model%mesh%nnode), source=0.0_dp)
        do i = 1, group%n
            associate (card => group%cards(i))
                call get_range(file, card, boundary_fields, 'BOUNDARY', 'node', &
                               model%mesh%nnode, n1, n2, inc, error)
                if (allocated(error)) return
                ctx = 'BOUNDARY '//to_text(n1)
                do k = 1, 2
                    call get_int(file, card, boundary_fields, 3 + k, ctx, 0, code(k), error)
                    if (allocated(error)) return
                    if (code(k) /= 0 .and. code(k) /= 1) then
                        call field_error(error, file, card, boundary_fields, 3 + k, ctx, &
                                         '0 (free) or 1 (prescribed)', to_text(code(k)))
                        return
                    end if
                    call get_real(file, card, boundary_fields, 5 + k, ctx, 0.0_dp, value(k), &
                                  error, given(k))
                    if (allocated(error)) return
                    if (given(k) .and. code(k) /= 1) then
                        call field_error(error, file, card, boundary_fields, 5 + k, ctx, &
                                         'blank: a prescribed value needs '// &
                                         trim(boundary_fields(3 + k)%name)//' = 1', &
                                         raw_text(card, boundary_fields, 5 + k))
                        return
                    end if
                end do
                if (all(code == 0)) then
                    call card_error(error, file, card, 'BOUNDARY card fixes nothing: '// &
                                    'set IX and/or IY to 1')
                    return
                end if
                do k = 1, 2
                    if (code(k) == 1) then
                        model%fixed(k, n1:n2:inc) = .true.
                        model%prescribed(k, n1:n2:inc) = value(k)
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
        integer :: i, n1, n2, inc, ngravity, npressure
        real(dp) :: force(2)
        set%name = group%name
        allocate (set%nodal_force(2, model%mesh%nnode), source=0.0_dp)
        allocate (set%gravity(group%n), set%pressures(group%n))
        ngravity = 0
        npressure = 0
        do i = 1, group%n
            associate (card => group%cards(i))
                call get_text(card, gravity_fields, 1, keyword)
                keyword = upper(keyword)
                select case (keyword)
                case ('GRAVITY')
                    call get_text(card, gravity_fields, 2, name)
                    name = upper(name)
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
                    call get_real(file, card, gravity_fields, 3, 'GRAVITY', 0.0_dp, &
                                  gravity%ax, error)
                    if (allocated(error)) return
                    call get_real(file, card, gravity_fields, 4, 'GRAVITY', -1.0_dp, &
                                  gravity%ay, error)
                    if (allocated(error)) return
                    ngravity = ngravity + 1
                    set%gravity(ngravity) = gravity
                case ('FORCE')
                    call get_range(file, card, force_fields, 'FORCE', 'node', &
                                   model%mesh%nnode, n1, n2, inc, error, offset=1)
                    if (allocated(error)) return
                    call get_real(file, card, force_fields, 5, 'FORCE', 0.0_dp, force(1), error)
                    if (allocated(error)) return
                    call get_real(file, card, force_fields, 6, 'FORCE', 0.0_dp, force(2), error)
                    if (allocated(error)) return
                    set%nodal_force(1, n1:n2:inc) = set%nodal_force(1, n1:n2:inc) + force(1)
                    set%nodal_force(2, n1:n2:inc) = set%nodal_force(2, n1:n2:inc) + force(2)
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

    !> The STAGES group; without one, a single LOAD stage of the default load set.
    subroutine read_stages(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: keyword, name, date, label, ctx
        integer :: i, k, g
        logical :: given, creeping
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
                call get_text(card, stage_fields, 1, keyword)
                keyword = upper(keyword)
                ctx = 'STAGES '//keyword
                call get_text(card, stage_fields, 4, date)
                call get_text(card, stage_fields, 5, label)
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
                    call get_text(card, stage_fields, 2, name)
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
                    call get_text(card, load_stage_fields, 2, name)
                    name = upper(name)
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
                    call get_real(file, card, water_stage_fields, 2, ctx, 0.0_dp, &
                                  stage%level, error, given)
                    if (allocated(error)) return
                    if (.not. given) then
                        call field_error(error, file, card, water_stage_fields, 2, ctx, &
                                         'the reservoir level to reach (m)', '')
                        return
                    end if
                    stage%label = 'WATER '//level_text(stage%level)//stage%label(6:)
                case ('WET')
                    stage%kind = stage_wet
                    if (.not. has_wetting(model)) then
                        call card_error(error, file, card, 'WET stage, but no material '// &
                                        'has a WETTING card (nothing would collapse)')
                        return
                    end if
                    ! blank: every element; else those whose centroid lies below LEVEL
                    call get_real(file, card, water_stage_fields, 2, ctx, huge(1.0_dp), &
                                  stage%level, error, given)
                    if (allocated(error)) return
                    if (given) stage%label = 'WET '//level_text(stage%level)//stage%label(4:)
                case default
                    call card_error(error, file, card, "unknown stage '"//keyword// &
                                    "' in STAGES: expected FILL, LOAD, RESET, WATER, WAIT or WET")
                    return
                end select
                call get_int(file, card, stage_fields, 3, ctx, 1, stage%increments, error)
                if (allocated(error)) return
                if (stage%increments < 1 .or. stage%increments > 100000) then
                    call field_error(error, file, card, stage_fields, 3, ctx, &
                                     'a number of increments from 1 to 100000', &
                                     raw_text(card, stage_fields, 3))
                    return
                end if
            end associate
        end do
    end subroutine read_stages

    !> RESERVOIR: the element faces the reservoir wets, each with the group whose placement
    !> covers it (blank: never covered).
    !> CONTACT: SURFACE cards (element faces, generated with NGEN and INC; cards of one name
    !> add up) and PAIR cards (slave, master, friction, closure tolerance, scheme, search,
    !> cast in place). docs/cards.md, CONTACT.
    subroutine read_contact(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: keyword, name, ctx, word
        integer, allocatable :: first_line(:), used_as(:), owner(:)
        integer :: i, k, e, face, ngen, inc, s, node, side, j, cast
        type(contact_pair_t) :: pair
        allocate (model%surfaces(0), model%contact_pairs(0), first_line(0))
        if (.not. group%present) return
        if (group%n == 0) then
            call fatal_error(error, file//':'//to_text(group%header_line)//': CONTACT has '// &
                             'no SURFACE or PAIR cards', input_error)
            return
        end if
        do i = 1, group%n
            associate (card => group%cards(i))
                call get_text(card, surface_fields, 1, keyword)
                if (upper(keyword) /= 'SURFACE') cycle
                call get_text(card, surface_fields, 2, name)
                name = upper(name)
                if (len(name) == 0) then
                    call field_error(error, file, card, surface_fields, 2, 'CONTACT SURFACE', &
                                     'a surface name', '')
                    return
                end if
                ctx = 'CONTACT SURFACE '//name
                s = surface_index(name)
                if (s == 0) then
                    model%surfaces = [model%surfaces, contact_surface_t(name=name)]
                    s = size(model%surfaces)
                    allocate (model%surfaces(s)%element(0), model%surfaces(s)%face(0))
                    first_line = [first_line, card%line]
                end if
                call get_int(file, card, surface_fields, 3, ctx, 0, e, error)
                if (allocated(error)) return
                call get_int(file, card, surface_fields, 4, ctx, 0, face, error)
                if (allocated(error)) return
                if (face < 1 .or. face > 4) then
                    call field_error(error, file, card, surface_fields, 4, ctx, &
                                     'a face from 1 to 4', raw_text(card, surface_fields, 4))
                    return
                end if
                call get_int(file, card, surface_fields, 5, ctx, 0, ngen, error)
                if (allocated(error)) return
                if (ngen < 0) then
                    call field_error(error, file, card, surface_fields, 5, ctx, 'an integer >= 0', &
                                     raw_text(card, surface_fields, 5))
                    return
                end if
                call get_int(file, card, surface_fields, 6, ctx, 1, inc, error)
                if (allocated(error)) return
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
                call get_text(card, pair_fields, 1, keyword)
                if (upper(keyword) /= 'PAIR') cycle
                pair = contact_pair_t(line=card%line)
                do side = 2, 3
                    call get_text(card, pair_fields, side, name)
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
                call get_real(file, card, pair_fields, 4, ctx, 0.0_dp, pair%friction, error)
                if (allocated(error)) return
                if (.not. (pair%friction >= 0.0_dp)) then
                    call field_error(error, file, card, pair_fields, 4, ctx, 'a real >= 0', &
                                     raw_text(card, pair_fields, 4))
                    return
                end if
                call get_real(file, card, pair_fields, 5, ctx, 0.0_dp, pair%tolerance, error)
                if (allocated(error)) return
                if (.not. (pair%tolerance >= 0.0_dp)) then
                    call field_error(error, file, card, pair_fields, 5, ctx, 'a real >= 0 (m)', &
                                     raw_text(card, pair_fields, 5))
                    return
                end if
                call get_text(card, pair_fields, 6, word)
                select case (upper(word))
                case ('', 'MORTAR')
                    pair%scheme = scheme_mortar
                case ('NTS')
                    pair%scheme = scheme_nts
                case default
                    call field_error(error, file, card, pair_fields, 6, ctx, &
                                     'MORTAR (segment-to-segment) or NTS (node-to-segment)', &
                                     word)
                    return
                end select
                call get_text(card, pair_fields, 7, word)
                select case (upper(word))
                case ('', 'LINEAR')
                    pair%search = search_linear
                case ('RPIM')
                    pair%search = search_rpim
                case default
                    call field_error(error, file, card, pair_fields, 7, ctx, &
                                     'LINEAR (piecewise-linear master surface) or RPIM '// &
                                     '(radial point interpolation)', word)
                    return
                end select
                if (pair%search == search_rpim .and. pair%scheme == scheme_nts) then
                    call field_error(error, file, card, pair_fields, 7, ctx, &
                                     'LINEAR with SCHEME NTS (RPIM serves the mortar '// &
                                     'scheme)', word)
                    return
                end if
                call get_int(file, card, pair_fields, 8, ctx, 0, cast, error)
                if (allocated(error)) return
                if (cast /= 0 .and. cast /= 1) then
                    call field_error(error, file, card, pair_fields, 8, ctx, &
                                     '0 or 1 (1: cast in place, the gap at placement counts '// &
                                     'as closed)', raw_text(card, pair_fields, 8))
                    return
                end if
                pair%cast = cast == 1
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

    subroutine read_reservoir(file, group, model, error)
        character(len=*), intent(in) :: file
        type(group_cards_t), intent(in) :: group
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: name, ctx
        integer :: i, j
        allocate (model%wet_faces(group%n))
        if (group%present .and. group%n == 0) then
            call fatal_error(error, file//':'//to_text(group%header_line)//': RESERVOIR '// &
                             'has no face cards', input_error)
            return
        end if
        do i = 1, group%n
            associate (card => group%cards(i), wet => model%wet_faces(i))
                call get_int(file, card, reservoir_fields, 1, 'RESERVOIR', 0, wet%element, &
                             error)
                if (allocated(error)) return
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
                call get_int(file, card, reservoir_fields, 2, ctx, 0, wet%face, error)
                if (allocated(error)) return
                if (wet%face < 1 .or. wet%face > 4) then
                    call field_error(error, file, card, reservoir_fields, 2, ctx, &
                                     'a face from 1 to 4', raw_text(card, reservoir_fields, 2))
                    return
                end if
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
                call get_text(card, reservoir_fields, 3, name)
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
        character(len=:), allocatable :: name, label
        integer :: i, j
        allocate (model%gauges(group%n))
        if (group%present .and. group%n == 0) then
            call fatal_error(error, file//':'//to_text(group%header_line)//': GAUGES has '// &
                             'no gauge cards', input_error)
            return
        end if
        do i = 1, group%n
            associate (card => group%cards(i), gauge => model%gauges(i))
                call get_int(file, card, gauge_fields, 1, 'GAUGES', 0, gauge%node, error)
                if (allocated(error)) return
                if (gauge%node < 1 .or. gauge%node > model%mesh%nnode) then
                    call field_error(error, file, card, gauge_fields, 1, 'GAUGES', &
                                     'a node from 1 to '//to_text(model%mesh%nnode), &
                                     raw_text(card, gauge_fields, 1))
                    return
                end if
                call get_text(card, gauge_fields, 2, name)
                if (len(name) == 0) then
                    call field_error(error, file, card, gauge_fields, 2, &
                                     'GAUGES '//to_text(gauge%node), 'a gauge name', '')
                    return
                end if
                gauge%name = upper(name)
                do j = 1, i - 1
                    if (model%gauges(j)%name == gauge%name) then
                        call field_error(error, file, card, gauge_fields, 2, &
                                         'GAUGES '//to_text(gauge%node), &
                                         'a name not used before (line '// &
                                         to_text(group%cards(j)%line)//')', name)
                        return
                    end if
                end do
                call get_text(card, gauge_fields, 3, label)
                gauge%label = label
            end associate
        end do
    end subroutine read_gauges

    subroutine read_pressure(file, card, model, pressure, error)
        character(len=*), intent(in) :: file
        type(card_t), intent(in) :: card
        type(model_t), intent(in) :: model
        type(pressure_load_t), intent(out) :: pressure
        type(error_t), allocatable, intent(out) :: error
        logical :: given
        call get_int(file, card, pressure_fields, 2, 'PRESSURE', 0, pressure%element, error)
        if (allocated(error)) return
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
        call get_int(file, card, pressure_fields, 3, 'PRESSURE', 0, pressure%face, error)
        if (allocated(error)) return
        if (pressure%face < 1 .or. pressure%face > 4) then
            call field_error(error, file, card, pressure_fields, 3, 'PRESSURE', &
                             'a face from 1 to 4', raw_text(card, pressure_fields, 3))
            return
        end if
        associate (conn => model%mesh%conn(:, pressure%element))
            if (pressure%face == 3 .and. conn(3) == conn(4)) then
                call field_error(error, file, card, pressure_fields, 3, 'PRESSURE', &
                                 'face 1, 2 or 4: element '//to_text(pressure%element)// &
                                 ' is a triangle, its face 3 has zero length', '3')
                return
            end if
        end associate
        call get_real(file, card, pressure_fields, 4, 'PRESSURE', 0.0_dp, pressure%p1, error)
        if (allocated(error)) return
        call get_real(file, card, pressure_fields, 5, 'PRESSURE', pressure%p1, pressure%p2, &
                      error, given)
    end subroutine read_pressure

    !> Numbers 1..n with none missing, and n equal to the CONTROL count when one was given.
    subroutine check_numbering(file, header_line, what, defined_line, announced, count_name, &
                               control_line, error)
        character(len=*), intent(in) :: file, what, count_name
        integer, intent(in) :: header_line, defined_line(:), announced, control_line
        type(error_t), allocatable, intent(out) :: error
        integer :: missing
        missing = findloc(defined_line, 0, dim=1)
        if (missing > 0) then
            call fatal_error(error, file//':'//to_text(header_line)//': missing '//what//' '// &
                             to_text(missing)//' ('//what//'s must be numbered 1 to '// &
                             to_text(size(defined_line))//' without gaps)', input_error)
            return
        end if
        if (announced > 0 .and. announced /= size(defined_line)) then
            call fatal_error(error, file//':'//to_text(control_line)//': field '//count_name// &
                             ' of CONTROL: '//to_text(announced)//' '//what// &
                             's announced, '//to_text(size(defined_line))//' read', input_error)
        end if
    end subroutine check_numbering

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

    subroutine get_positive(file, card, fields, k, ctx, default, value, error)
        character(len=*), intent(in) :: file, ctx
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        real(dp), intent(in) :: default
        real(dp), intent(out) :: value
        type(error_t), allocatable, intent(out) :: error
        call get_real(file, card, fields, k, ctx, default, value, error)
        if (allocated(error)) return
        if (.not. value > 0.0_dp) call field_error(error, file, card, fields, k, ctx, &
                                                   'a real > 0', raw_text(card, fields, k))
    end subroutine get_positive

    function raw_text(card, fields, k) result(text)
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        character(len=:), allocatable :: text
        call get_text(card, fields, k, text)
    end function raw_text

    function real_text(card, fields, k) result(text)
        type(card_t), intent(in) :: card
        type(field_t), intent(in) :: fields(:)
        integer, intent(in) :: k
        character(len=:), allocatable :: text
        call get_text(card, fields, k, text)
        if (len(text) == 0) text = '(blank)'
    end function real_text

    !> Index of `word` in `names` (blank-padded comparison), 0 if absent. (gfortran 12's
    !> findloc compares character arrays of unequal length wrongly.)
    pure integer function position(names, word)
        character(len=*), intent(in) :: names(:), word
        integer :: i
        position = 0
        do i = 1, size(names)
            if (names(i) == word) then
                position = i
                return
            end if
        end do
    end function position

    function group_list(names) result(text)
        character(len=*), intent(in) :: names(:)
        character(len=:), allocatable :: text
        integer :: i
        if (size(names) == 0) then
            text = 'the deck names none'
            return
        end if
        text = trim(names(1))
        do i = 2, size(names)
            text = text//', '//trim(names(i))
        end do
    end function group_list
end module cfrd_deck
