!> Tests of the deck reader on valid decks: every value checked against the card manual
!> (docs/cards.md) worked out by hand. The bad decks are checked through the command line
!> (test/bad_decks, tools/run_tests.sh); a few are repeated here at library level to show
!> that the reader returns an input error rather than stopping.
module test_io_deck
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, input_error
    use cfrd_testing, only: unittest_t, new_unittest, check, fail
    use cfrd_model, only: model_t, mesh_t, all_groups
    use cfrd_model_check, only: element_shape, free_rigid_mode, shape_ok, shape_degenerate, &
                                shape_inverted
    use cfrd_deck, only: read_deck
    implicit none
    private

    public :: collect_io_deck

    character(len=*), parameter :: dir = 'build/test-decks/'
    character(len=*), parameter :: nl = new_line('a')
    character(len=*), parameter :: node_line_1 = &
        '    1    3    1       0.0       0.0       4.0       0.0'//nl
    character(len=*), parameter :: node_line_2 = &
        '    4    6    1       0.0       1.0       4.0       1.0'//nl
    character(len=*), parameter :: std_nodes = node_line_1//node_line_2
    character(len=*), parameter :: std_elements = '    1    1    2    5    4    1    1'//nl
    character(len=*), parameter :: std_materials = '    1ELASTIC   soil'//nl// &
        '   20000.0       0.3      20.0'//nl
    character(len=*), parameter :: std_boundary = '    1    3    1    1    1'//nl

contains

    subroutine collect_io_deck(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('node_generation', test_node_generation), &
                new_unittest('element_generation_and_groups', test_element_generation), &
                new_unittest('defaults', test_defaults), &
                new_unittest('triangle', test_triangle), &
                new_unittest('free_format_equals_fixed', test_free_format), &
                new_unittest('loads', test_loads), &
                new_unittest('control_card', test_control), &
                new_unittest('comments_blank_lines_crlf', test_comments_crlf), &
                new_unittest('utf8_byte_order_mark', test_utf8_bom), &
                new_unittest('fortran_real_syntax', test_real_syntax), &
                new_unittest('bad_deck_is_an_input_error', test_bad_deck_error), &
                new_unittest('bad_unknown_group', bad_unknown_group), &
                new_unittest('bad_missing_nodes', bad_missing_nodes), &
                new_unittest('bad_missing_elements', bad_missing_elements), &
                new_unittest('bad_missing_materials', bad_missing_materials), &
                new_unittest('bad_missing_boundary', bad_missing_boundary), &
                new_unittest('bad_duplicate_group', bad_duplicate_group), &
                new_unittest('bad_no_end_card', bad_no_end_card), &
                new_unittest('bad_card_before_header', bad_card_before_header), &
                new_unittest('bad_integer_not_numeric', bad_integer_not_numeric), &
                new_unittest('bad_real_not_numeric', bad_real_not_numeric), &
                new_unittest('bad_embedded_blank', bad_embedded_blank), &
                new_unittest('bad_real_in_integer_field', bad_real_in_integer_field), &
                new_unittest('bad_negative_modulus', bad_negative_modulus), &
                new_unittest('bad_poisson_half', bad_poisson_half), &
                new_unittest('bad_nnode_mismatch', bad_nnode_mismatch), &
                new_unittest('bad_nelem_mismatch', bad_nelem_mismatch), &
                new_unittest('bad_nmat_mismatch', bad_nmat_mismatch), &
                new_unittest('bad_duplicate_node', bad_duplicate_node), &
                new_unittest('bad_missing_node', bad_missing_node), &
                new_unittest('bad_element_names_missing_node', bad_element_names_missing_node), &
                new_unittest('bad_repeated_node', bad_repeated_node), &
                new_unittest('bad_inverted_element', bad_inverted_element), &
                new_unittest('bad_degenerate_element', bad_degenerate_element), &
                new_unittest('bad_material_out_of_range', bad_material_out_of_range), &
                new_unittest('bad_missing_material_card', bad_missing_material_card), &
                new_unittest('bad_unknown_law', bad_unknown_law), &
                new_unittest('bad_unused_node', bad_unused_node), &
                new_unittest('bad_rigid_no_support', bad_rigid_no_support), &
                new_unittest('bad_rigid_only_x', bad_rigid_only_x), &
                new_unittest('bad_rigid_rotation', bad_rigid_rotation), &
                new_unittest('bad_unknown_load_keyword', bad_unknown_load_keyword), &
                new_unittest('bad_unknown_gravity_group', bad_unknown_gravity_group), &
                new_unittest('bad_pressure_face_range', bad_pressure_face_range), &
                new_unittest('bad_pressure_triangle_face3', bad_pressure_triangle_face3), &
                new_unittest('bad_beyond_column_80', bad_beyond_column_80), &
                new_unittest('bad_tab_on_fixed_card', bad_tab_on_fixed_card), &
                new_unittest('bad_units_not_kn_m', bad_units_not_kn_m), &
                new_unittest('bad_model_type', bad_model_type), &
                new_unittest('bad_increment_not_divisor', bad_increment_not_divisor), &
                new_unittest('bad_free_format_bad_real', bad_free_format_bad_real), &
                new_unittest('bad_pa_not_positive', bad_pa_not_positive), &
                new_unittest('bad_x2_required', bad_x2_required), &
                new_unittest('bad_boundary_code', bad_boundary_code), &
                new_unittest('bad_duplicate_element', bad_duplicate_element), &
                new_unittest('bad_real_overflow', bad_real_overflow), &
                new_unittest('bad_indented_word_is_data', bad_indented_word), &
                new_unittest('bad_free_format_extra_field', bad_free_extra_field), &
                new_unittest('bad_free_format_lone_ampersand', bad_lone_ampersand), &
                new_unittest('free_format_trailing_comma_and_label', test_free_trailing), &
                new_unittest('shape_check', test_shape_check), &
                new_unittest('rigid_mode_check', test_rigid_mode_check), &
                new_unittest('missing_file', test_missing_file) &
                ]
    end subroutine collect_io_deck

    !> Write `text` to build/test-decks/<name> and read it.
    subroutine read_text(name, text, model, error)
        character(len=*), intent(in) :: name, text
        type(model_t), intent(out) :: model
        type(error_t), allocatable, intent(out) :: error
        integer :: unit
        call execute_command_line('mkdir -p '//dir)
        open (newunit=unit, file=dir//name, access='stream', form='unformatted', &
              status='replace', action='write')
        write (unit) text
        close (unit)
        call read_deck(dir//name, model, error)
    end subroutine read_text

    !> A 2 x 1 strip of quads: nodes 1-3 at y = 0 and 4-6 at y = 1, x = 0, 2, 4.
    function strip_deck(nodes, elements, extra_loads) result(text)
        character(len=*), intent(in) :: nodes, elements, extra_loads
        character(len=:), allocatable :: text
        text = 'TITLE     strip'//nl// &
               'NODES'//nl//nodes// &
               'ELEMENTS'//nl//elements// &
               'MATERIALS'//nl// &
               '    1ELASTIC   soil'//nl// &
               '   20000.0       0.3      20.0'//nl// &
               'BOUNDARY'//nl// &
               '    1    3    1    1    1'//nl// &
               'LOADS'//nl//extra_loads// &
               'END'//nl
    end function strip_deck

    function standard_nodes() result(text)
        character(len=:), allocatable :: text
        text = '    1    3    1       0.0       0.0       4.0       0.0'//nl// &
               '    4    6    1       0.0       1.0       4.0       1.0'//nl
    end function standard_nodes

    !> Node N1 + k INC sits at P1 + k/m (P2 - P1): node 5 is the middle of 4 -> 6, (2, 1);
    !> with INC = 2 over 1..5 nodes 1, 3, 5 at x = 0, 2, 4 (manual, NODES, generation).
    subroutine test_node_generation(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        call read_text('nodes.dat', strip_deck(standard_nodes(), &
                       '    1    1    2    5    4    1    1'//nl, ''), model, error)
        if (allocated(error)) return
        call check(error, model%mesh%nnode, 6, 'nodes')
        if (allocated(error)) return
        call check(error, model%mesh%x(1, 5), 2.0_dp, 'x of node 5', abs=1e-15_dp)
        if (allocated(error)) return
        call check(error, model%mesh%x(2, 5), 1.0_dp, 'y of node 5', abs=1e-15_dp)
        if (allocated(error)) return
        call read_text('nodes-inc.dat', strip_deck( &
                       '    1    5    2       0.0       0.0       4.0       0.0'//nl// &
                       '    2    6    2       0.0       1.0       4.0       1.0'//nl, &
                       '    1    1    3    4    2    1    1    2'//nl, ''), model, error)
        if (allocated(error)) return
        call check(error, model%mesh%x(1, 3), 2.0_dp, 'x of node 3 (INC 2)', abs=1e-15_dp)
        if (allocated(error)) return
        call check(error, model%mesh%x(2, 4), 1.0_dp, 'y of node 4 (INC 2)', abs=1e-15_dp)
    end subroutine test_node_generation

    !> Element NE + g has nodes I + g NINC ...: element 2 of '1 1 2 5 4 1 1' is 2 3 6 5.
    subroutine test_element_generation(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        integer :: k
        integer, parameter :: expected(4) = [2, 3, 6, 5]
        call read_text('elements.dat', strip_deck(standard_nodes(), &
                       '    1    1    2    5    4    1    1    1 soil'//nl, ''), model, error)
        if (allocated(error)) return
        call check(error, model%mesh%nelem, 2, 'elements')
        if (allocated(error)) return
        do k = 1, 4
            call check(error, model%mesh%conn(k, 2), expected(k), 'node of element 2')
            if (allocated(error)) return
        end do
        call check(error, model%mesh%group(2), 1, 'group of element 2')
        if (allocated(error)) return
        call check(error, trim(model%mesh%group_name(1)), 'SOIL', 'group name upper-cased')
    end subroutine test_element_generation

    !> Blank fields take the manual's defaults: N2 = N1, INC = 1, X1 = Y1 = 0, GAMMA = 0 ...
    subroutine test_defaults(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        call read_text('defaults.dat', &
                       'NODES'//nl// &
                       '    1'//nl// &
                       '    2               1.0'//nl// &
                       '    3               1.0       1.0'//nl// &
                       '    4                         1.0'//nl// &
                       'ELEMENTS'//nl// &
                       '    1    1    2    3    4    1'//nl// &
                       'MATERIALS'//nl// &
                       '    1elastic'//nl// &
                       '   20000.0       0.3'//nl// &
                       'BOUNDARY'//nl// &
                       '    1    2    1    1    1'//nl// &
                       'END'//nl, model, error)
        if (allocated(error)) return
        call check(error, model%mesh%x(1, 1), 0.0_dp, 'blank X1', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%mesh%x(2, 4), 1.0_dp, 'Y1 of node 4', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%materials(1)%unit_weight, 0.0_dp, 'blank GAMMA', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%pa, 101.325_dp, 'default PA', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%gamma_w, 9.81_dp, 'default GAMMAW', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, size(model%load_sets(1)%gravity), 0, 'no loads without LOADS')
        if (allocated(error)) return
        call check(error, model%prescribed(1, 2), 0.0_dp, 'blank UX', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%mesh%group(1), 0, 'blank GROUP')
    end subroutine test_defaults

    !> A blank L makes a triangle, stored with node 4 = node 3.
    subroutine test_triangle(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        call read_text('triangle.dat', strip_deck(standard_nodes(), &
                       '    1    1    2    5'//nl// &
                       '    2    1    5    4'//nl// &
                       '    3    2    3    6    5    1'//nl, ''), model, error)
        if (allocated(error)) then
            ! MAT of elements 1 and 2 is blank: the manual says required.
            if (index(error%message, 'field MAT of ELEMENTS 1') > 0) then
                deallocate (error)
            else
                return
            end if
        else
            call fail(error, 'a blank MAT was accepted')
            return
        end if
        call read_text('triangle.dat', strip_deck(standard_nodes(), &
                       '    1    1    2    5         1'//nl// &
                       '    2    1    5    4         1'//nl// &
                       '    3    2    3    6    5    1'//nl, ''), model, error)
        if (allocated(error)) return
        call check(error, model%mesh%conn(4, 1), model%mesh%conn(3, 1), 'node 4 = node 3')
        if (allocated(error)) return
        call check(error, model%mesh%conn(4, 2), 4, 'node 3 of triangle 2')
    end subroutine test_triangle

    !> The same deck in & free format gives the same model, bit for bit.
    subroutine test_free_format(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: fixed, free
        call read_text('fixed.dat', strip_deck(standard_nodes(), &
                       '    1    1    2    5    4    1    1    1 SOIL'//nl, &
                       'GRAVITY   SOIL            0.5      -1.0'//nl), fixed, error)
        if (allocated(error)) return
        call read_text('free.dat', strip_deck( &
                       '&1, 3, 1, 0.0, 0.0, 4.0, 0.0'//nl// &
                       '&4,6,1,0,1,4,1'//nl, &
                       '& 1, 1, 2, 5, 4, 1, 1, 1, soil'//nl, &
                       '&GRAVITY, SOIL, 0.5, -1.0'//nl), free, error)
        if (allocated(error)) return
        call check(error, all(fixed%mesh%x == free%mesh%x), 'coordinates equal')
        if (allocated(error)) return
        call check(error, all(fixed%mesh%conn == free%mesh%conn), 'connectivity equal')
        if (allocated(error)) return
        call check(error, free%load_sets(1)%gravity(1)%ax, 0.5_dp, 'AX in free format', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, free%load_sets(1)%gravity(1)%group, 1, 'gravity group in free format')
    end subroutine test_free_format

    !> GRAVITY, FORCE (added over a range) and PRESSURE (P2 defaults to P1).
    subroutine test_loads(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        call read_text('loads.dat', strip_deck(standard_nodes(), &
                       '    1    1    2    5    4    1    1'//nl, &
                       'GRAVITY'//nl// &
                       'FORCE         4    6    2      10.0      -5.0'//nl// &
                       'FORCE         6                 1.5'//nl// &
                       'PRESSURE      2    2      30.0'//nl), model, error)
        if (allocated(error)) return
        call check(error, model%load_sets(1)%gravity(1)%group, all_groups, 'blank group is ALL')
        if (allocated(error)) return
        call check(error, model%load_sets(1)%gravity(1)%ay, -1.0_dp, 'default AY', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%load_sets(1)%nodal_force(1, 6), 11.5_dp, &
                   'FX at node 6 (10 + 1.5)', &
                   abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%load_sets(1)%nodal_force(2, 4), -5.0_dp, 'FY at node 4', &
                   abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%load_sets(1)%nodal_force(2, 5), 0.0_dp, &
                   'node 5 skipped by INC', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%load_sets(1)%pressures(1)%face, 2, 'face')
        if (allocated(error)) return
        call check(error, model%load_sets(1)%pressures(1)%p2, 30.0_dp, &
                   'P2 defaults to P1', abs=0.0_dp)
    end subroutine test_loads

    subroutine test_control(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        call read_text('control.dat', 'CONTROL'//nl// &
                       '    6    2    1    1     100.0      10.0 kn-m'//nl// &
                       strip_deck(standard_nodes(), '    1    1    2    5    4    1    1'//nl, &
                                  ''), model, error)
        if (allocated(error)) return
        call check(error, model%pa, 100.0_dp, 'PA', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%gamma_w, 10.0_dp, 'GAMMAW', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%title, 'strip', 'title from columns 11-80')
    end subroutine test_control

    !> Comment cards (* and C), blank lines and CRLF line ends change nothing.
    subroutine test_comments_crlf(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        character(len=:), allocatable :: text
        character(len=*), parameter :: cr = achar(13)
        text = '* a comment'//cr//nl//'C another one'//cr//nl//cr//nl// &
               'NODES'//cr//nl// &
               '    1    3    1       0.0       0.0       4.0       0.0'//cr//nl// &
               'c lower-case comment'//nl// &
               '    4    6    1       0.0       1.0       4.0       1.0'//cr//nl// &
               'ELEMENTS'//cr//nl//'    1    1    2    5    4    1    1'//cr//nl// &
               'MATERIALS'//cr//nl//'    1ELASTIC'//cr//nl//'   20000.0       0.3'//cr//nl// &
               'BOUNDARY'//cr//nl//'    1    3    1    1    1'//cr//nl//'STOP'//cr//nl
        call read_text('crlf.dat', text, model, error)
        if (allocated(error)) return
        call check(error, model%mesh%x(1, 6), 4.0_dp, 'x of node 6', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%mesh%nelem, 2, 'elements')
    end subroutine test_comments_crlf

    !> A UTF-8 byte-order mark before the first card is skipped: a deck whose first card is a
    !> header (the fault: 'data card before any group header') reads as without it, with its
    !> columns counted from the first character after the mark.
    subroutine test_utf8_bom(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        character(len=*), parameter :: bom = achar(239)//achar(187)//achar(191)
        call read_text('bom.dat', bom//'NODES'//nl//standard_nodes()// &
                       'ELEMENTS'//nl//'    1    1    2    5    4    1    1'//nl// &
                       'MATERIALS'//nl//'    1ELASTIC'//nl//'   20000.0       0.3'//nl// &
                       'BOUNDARY'//nl//'    1    3    1    1    1'//nl//'END'//nl, model, error)
        if (allocated(error)) return
        call check(error, model%mesh%x(1, 6), 4.0_dp, 'x of node 6', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%mesh%nelem, 2, 'elements')
    end subroutine test_utf8_bom

    !> F10.0 fields in Fortran syntax: '2.0D4', '20000', '.2E5', '2E+004', '20D+003' are all
    !> 20000; '.25' is 0.25.
    subroutine test_real_syntax(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        character(len=10), parameter :: spellings(5) = ['     2.0D4', '     20000', &
                                                        '      .2E5', '    2E+004', &
                                                        '   20D+003']
        integer :: i
        ! '    2E+004' puts its exponent letter in column 6, where card 1 has its LAW: it
        ! must still be read as the parameter card.
        do i = 1, 5
            call read_text('reals.dat', 'NODES'//nl//standard_nodes()//'ELEMENTS'//nl// &
                           '    1    1    2    5    4    1    1'//nl// &
                           'MATERIALS'//nl//'    1ELASTIC'//nl//spellings(i)//'       .25'//nl// &
                           'BOUNDARY'//nl//'    1    3    1    1    1'//nl//'END'//nl, &
                           model, error)
            if (allocated(error)) return
            call check(error, model%materials(1)%youngs_modulus, 20000.0_dp, &
                       'E spelled '//spellings(i), abs=0.0_dp)
            if (allocated(error)) return
        end do
        call check(error, model%materials(1)%poisson_ratio, 0.25_dp, 'NU = .25', abs=0.0_dp)
    end subroutine test_real_syntax

    subroutine test_bad_deck_error(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        call read_text('bad.dat', strip_deck(standard_nodes(), &
                       '    1    1    2    5    4    1    1'//nl, &
                       'PRESSURE      9    1'//nl), model, error)
        if (.not. allocated(error)) then
            call fail(error, 'element 9 of a 2-element mesh was accepted')
            return
        end if
        if (error%category /= input_error .or. index(error%message, &
            'bad.dat:13:11-15: field ELEM of PRESSURE: expected an element from 1 to 2, '// &
            "found '9'") == 0) then
            error%message = 'unexpected: '//error%message
            return
        end if
        deallocate (error)
    end subroutine test_bad_deck_error

    subroutine test_missing_file(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        call read_deck(dir//'no-such-deck.dat', model, error)
        if (.not. allocated(error)) then
            call fail(error, 'a missing file was accepted')
            return
        end if
        if (error%category /= input_error .or. &
            index(error%message, 'no-such-deck.dat: no such deck file') == 0) then
            error%message = 'unexpected: '//error%message
            return
        end if
        deallocate (error)
    end subroutine test_missing_file

    ! ---- Bad input: each case is the valid strip deck below with one fault. Line numbers and
    ! columns in the expected messages are counted by hand on that deck; the message format
    ! is the one of the card specification (file:line:cols: field NAME of GROUP ...).

    !> The valid strip deck, line by line: 1 NODES, 2-3 node cards, 4 ELEMENTS, 5 element
    !> card (elements 1 and 2), 6 MATERIALS, 7-8 material 1, 9 BOUNDARY, 10 its card, then
    !> `extra` from line 11, then END. `head` goes before everything (and shifts the lines);
    !> `omit` leaves out one group; `end` replaces the END card.
    function deck(head, nodes, elements, materials, boundary, extra, end, omit) result(text)
        character(len=*), intent(in), optional :: head, nodes, elements, materials, boundary
        character(len=*), intent(in), optional :: extra, end, omit
        character(len=:), allocatable :: text
        character(len=:), allocatable :: skip
        skip = ''
        if (present(omit)) skip = omit
        text = ''
        if (present(head)) text = head
        if (skip /= 'NODES') text = text//'NODES'//nl//pick(nodes, std_nodes)
        if (skip /= 'ELEMENTS') text = text//'ELEMENTS'//nl//pick(elements, std_elements)
        if (skip /= 'MATERIALS') text = text//'MATERIALS'//nl//pick(materials, std_materials)
        if (skip /= 'BOUNDARY') text = text//'BOUNDARY'//nl//pick(boundary, std_boundary)
        if (present(extra)) text = text//extra
        text = text//pick(end, 'END'//nl)
    end function deck

    pure function pick(given, default) result(text)
        character(len=*), intent(in), optional :: given
        character(len=*), intent(in) :: default
        character(len=:), allocatable :: text
        if (present(given)) then
            text = given
        else
            text = default
        end if
    end function pick

    !> Read `text` as build/test-decks/<name>: it must be rejected as an input error whose
    !> message starts with '<path><where>' and contains every one of `parts`.
    subroutine expect_rejected(error, name, where, text, parts)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: name, where, text
        character(len=*), intent(in) :: parts(:)
        type(model_t) :: model
        type(error_t), allocatable :: deck_error
        integer :: i
        call read_text(name, text, model, deck_error)
        if (.not. allocated(deck_error)) then
            call fail(error, name//': the bad deck was accepted')
            return
        end if
        if (deck_error%category /= input_error) then
            call fail(error, name//': not an input error: '//deck_error%message)
            return
        end if
        if (index(deck_error%message, dir//name//where) /= 1) then
            call fail(error, "message does not start with '"//dir//name//where//"': "// &
                      deck_error%message)
            return
        end if
        do i = 1, size(parts)
            if (index(deck_error%message, trim(parts(i))) == 0) then
                call fail(error, "message lacks '"//trim(parts(i))//"': "//deck_error%message)
                return
            end if
        end do
    end subroutine expect_rejected

    ! ---- Model checks without a deck (cfrd_model_check), on meshes built by hand.

    !> det J of the unit square 1-2-3-4 is positive; 1-4-3-2 (clockwise) inverted; an
    !> arrowhead (node 3 pulled inside, re-entrant corner) inverted; a triangle on a line
    !> degenerate; the triangle 1-2-3 (node 4 = node 3) fine.
    subroutine test_shape_check(error)
        type(error_t), allocatable, intent(out) :: error
        type(mesh_t) :: mesh
        integer, parameter :: conns(4, 5) = reshape([1, 2, 3, 4, 1, 4, 3, 2, 1, 2, 5, 4, &
                                                     1, 2, 6, 6, 1, 2, 3, 3], [4, 5])
        integer, parameter :: expected(5) = [shape_ok, shape_inverted, shape_inverted, &
                                             shape_degenerate, shape_ok]
        character(len=*), parameter :: what(5) = [character(len=12) :: 'square', &
                                                  'clockwise', 'arrowhead', 'flat', 'triangle']
        integer :: e
        mesh%nnode = 6
        mesh%nelem = 5
        ! Nodes 1-4 the unit square; 5 = (0.25, 0.25) makes 1-2-5-4 re-entrant at 5
        ! (cross product at node 5 of (4 - 5) x (2 - 5) < 0); 6 = (2, 0) is on line 1-2.
        mesh%x = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, &
                          0.25_dp, 0.25_dp, 2.0_dp, 0.0_dp], [2, 6])
        mesh%conn = conns
        do e = 1, 5
            call check(error, element_shape(mesh, e), expected(e), trim(what(e)))
            if (allocated(error)) return
        end do
    end subroutine test_shape_check

    !> Rigid modes of the unit square: nothing fixed frees x translation; all x fixed frees
    !> y translation; x at nodes 1 and 2 (y = 0) and y at node 1 frees the rotation about
    !> node 1; adding x at node 4 (y = 1) suppresses all three (hand: rows (1, 0, -y)
    !> of the x dofs at y = 0 and y = 1 and (0, 1, x) have rank 3).
    subroutine test_rigid_mode_check(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        model%mesh%nnode = 4
        model%mesh%nelem = 1
        model%mesh%x = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, &
                                0.0_dp, 1.0_dp], [2, 4])
        allocate (model%fixed(2, 4), source=.false.)
        call check(error, free_rigid_mode(model), 'translation in x', 'nothing fixed')
        if (allocated(error)) return
        model%fixed(1, :) = .true.
        call check(error, free_rigid_mode(model), 'translation in y', 'only x fixed')
        if (allocated(error)) return
        model%fixed(1, :) = [.true., .true., .false., .false.]
        model%fixed(2, 1) = .true.
        call check(error, free_rigid_mode(model), 'rotation', 'x on one line, y at one node')
        if (allocated(error)) return
        model%fixed(1, 4) = .true.
        call check(error, free_rigid_mode(model), '', 'x at two heights and y: all suppressed')
    end subroutine test_rigid_mode_check

    !> LODES on line 11 (after BOUNDARY card, line 10) is no keyword; the valid ones are listed.
    subroutine bad_unknown_group(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'unknown-group.dat', ":11: unknown group 'LODES'", &
                             deck(extra='LODES'//nl), &
                             [character(len=80) :: &
                             'TITLE, CONTROL, NODES, ELEMENTS, MATERIALS, BOUNDARY, LOADS'])
    end subroutine bad_unknown_group

    !> Each required group missing in turn: the message names the file only (spec).
    subroutine bad_missing_nodes(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'missing-nodes.dat', ': missing group NODES', &
                             deck(omit='NODES'), &
                             [character(len=80) ::])
    end subroutine bad_missing_nodes

    subroutine bad_missing_elements(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'missing-elements.dat', ': missing group ELEMENTS', &
                             deck(omit='ELEMENTS'), &
                             [character(len=80) ::])
    end subroutine bad_missing_elements

    subroutine bad_missing_materials(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'missing-materials.dat', ': missing group MATERIALS', &
                             deck(omit='MATERIALS'), &
                             [character(len=80) ::])
    end subroutine bad_missing_materials

    subroutine bad_missing_boundary(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'missing-boundary.dat', ': missing group BOUNDARY', &
                             deck(omit='BOUNDARY'), &
                             [character(len=80) ::])
    end subroutine bad_missing_boundary

    !> A second NODES header on line 11.
    subroutine bad_duplicate_group(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'duplicate-group.dat', &
                             ':11: duplicate group NODES (first at line 1)', &
                             deck(extra='NODES'//nl//'    7       9.0'//nl), &
                             [character(len=80) ::])
    end subroutine bad_duplicate_group

    !> The deck stops after the BOUNDARY card.
    subroutine bad_no_end_card(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'no-end.dat', ': no END card: is the deck truncated?', &
                             deck(end=''), &
                             [character(len=80) ::])
    end subroutine bad_no_end_card

    subroutine bad_card_before_header(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'before-header.dat', ':1: data card before any group header', &
                             deck(head='    1    3'//nl), &
                             [character(len=80) ::])
    end subroutine bad_card_before_header

    !> K is columns 16-20 of line 5.
    subroutine bad_integer_not_numeric(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'integer-not-numeric.dat', ':5:16-20: field K of ELEMENTS', &
                             deck(elements='    1    1    2   5x    4    1    1'//nl), &
                             [character(len=80) :: 'integer', "found '5x'"])
    end subroutine bad_integer_not_numeric

    !> X1 is columns 16-25.
    subroutine bad_real_not_numeric(error)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), parameter :: bad_x1 = &
            '    1    3    1       abc       0.0       4.0       0.0'//nl
        call expect_rejected(error, 'real-not-numeric.dat', ':2:16-25: field X1 of NODES', &
                             deck(nodes=bad_x1//node_line_2), &
                             [character(len=80) :: 'real', "found 'abc'"])
    end subroutine bad_real_not_numeric

    !> A blank inside an F10 field.
    subroutine bad_embedded_blank(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'embedded-blank.dat', ':8:1-10: field E of MATERIALS 1', &
                             deck(materials='    1ELASTIC'//nl//' 2000 00.0       0.3'//nl), &
                             [character(len=80) :: "found '2000 00.0'"])
    end subroutine bad_embedded_blank

    !> IX is I5, columns 16-20.
    subroutine bad_real_in_integer_field(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'real-in-integer.dat', ':10:16-20: field IX of BOUNDARY', &
                             deck(boundary='    1    3    1  1.0    1'//nl), &
                             [character(len=80) :: 'integer', "found '1.0'"])
    end subroutine bad_real_in_integer_field

    subroutine bad_negative_modulus(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'negative-e.dat', ':8:1-10: field E of MATERIALS 1', &
                             deck(materials='    1ELASTIC'//nl//'  -20000.0       0.3'//nl), &
                             [character(len=80) :: '> 0', "found '-20000.0'"])
    end subroutine bad_negative_modulus

    !> NU must be < 0.5.
    subroutine bad_poisson_half(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'poisson-half.dat', ':8:11-20: field NU of MATERIALS 1', &
                             deck(materials='    1ELASTIC'//nl//'   20000.0       0.5'//nl), &
                             [character(len=80) :: '0.5', "found '0.5'"])
    end subroutine bad_poisson_half

    !> CONTROL data card is line 2; 6 nodes read.
    subroutine bad_nnode_mismatch(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'nnode-mismatch.dat', ':2: field NNODE of CONTROL', &
                             deck(head='CONTROL'//nl//'    7'//nl), &
                             [character(len=80) :: '7 nodes', '6 read'])
    end subroutine bad_nnode_mismatch

    !> One card generating 2 elements.
    subroutine bad_nelem_mismatch(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'nelem-mismatch.dat', ':2: field NELEM of CONTROL', &
                             deck(head='CONTROL'//nl//'         3'//nl), &
                             [character(len=80) :: '3 elements', '2 read'])
    end subroutine bad_nelem_mismatch

    subroutine bad_nmat_mismatch(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'nmat-mismatch.dat', ':2: field NMAT of CONTROL', &
                             deck(head='CONTROL'//nl//'              2'//nl), &
                             [character(len=80) :: '2 materials', '1 read'])
    end subroutine bad_nmat_mismatch

    !> Node 3 comes from the line-2 card.
    subroutine bad_duplicate_node(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'duplicate-node.dat', &
                             ':4: duplicate node 3 (first defined at line 2)', &
                             deck(nodes=std_nodes//'    3               9.0'//nl), &
                             [character(len=80) ::])
    end subroutine bad_duplicate_node

    !> Nodes 1-3 and 5-7: node 4 is missing; the NODES header (line 1) is named.
    subroutine bad_missing_node(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'missing-node.dat', ':1: missing node 4', &
                             deck(nodes=node_line_1// &
                                  '    5    7    1       0.0       1.0       4.0       1.0'//nl), &
                             [character(len=80) ::])
    end subroutine bad_missing_node

    !> Node 9 does not exist (6 nodes).
    subroutine bad_element_names_missing_node(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'element-missing-node.dat', &
                             ':5:16-20: field K of ELEMENTS 1', &
                             deck(elements='    1    1    2    9    4    1'//nl), &
                             [character(len=80) :: "found '9'"])
    end subroutine bad_element_names_missing_node

    !> I = J = 1.
    subroutine bad_repeated_node(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'repeated-node.dat', ':5: element 1 repeats a node', &
                             deck(elements='    1    1    1    5    4    1'//nl), &
                             [character(len=80) ::])
    end subroutine bad_repeated_node

    !> 1-4-5-2 goes round clockwise.
    subroutine bad_inverted_element(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'inverted.dat', ':5: element 1 is inverted', &
                             deck(elements='    1    1    4    5    2    1    1'//nl), &
                             [character(len=80) :: 'clockwise'])
    end subroutine bad_inverted_element

    !> Triangle 1-2-3 on the line y = 0 has zero area.
    subroutine bad_degenerate_element(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'degenerate.dat', ':6: element 3 is degenerate', &
                             deck(elements=std_elements//'    3    1    2    3         1'//nl), &
                             [character(len=80) ::])
    end subroutine bad_degenerate_element

    !> Only material 1 exists.
    subroutine bad_material_out_of_range(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'material-range.dat', ':5:26-30: field MAT of ELEMENTS 1', &
                             deck(elements='    1    1    2    5    4    2    1'//nl), &
                             [character(len=80) :: "found '2'"])
    end subroutine bad_material_out_of_range

    !> Card 2 of material 1 is missing.
    subroutine bad_missing_material_card(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'missing-material-card.dat', &
                             ':7: MATERIALS 1: missing parameter card', &
                             deck(materials='    1ELASTIC'//nl), &
                             [character(len=80) ::])
    end subroutine bad_missing_material_card

    subroutine bad_unknown_law(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'unknown-law.dat', ':7:6-15: field LAW of MATERIALS 1', &
                             deck(materials='    1PLASTIC'//nl//'   20000.0       0.3'//nl), &
                             [character(len=80) :: "found 'PLASTIC'"])
    end subroutine bad_unknown_law

    !> Node 7 (line 4) belongs to no element.
    subroutine bad_unused_node(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'unused-node.dat', ':4: node 7 is used by no element', &
                             deck(nodes=std_nodes//'    7               9.0       9.0'//nl), &
                             [character(len=80) ::])
    end subroutine bad_unused_node

    !> An empty BOUNDARY group: every rigid mode is free; translation in x is named first.
    subroutine bad_rigid_no_support(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'rigid-none.dat', &
                             ':9: rigid-body motion not suppressed: translation in x', &
                             deck(boundary=''), [character(len=80) ::])
    end subroutine bad_rigid_no_support

    !> Only x fixed: translation in y is free; the BOUNDARY header is line 9.
    subroutine bad_rigid_only_x(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'rigid-only-x.dat', &
                             ':9: rigid-body motion not suppressed: translation in y', &
                             deck(boundary='    1    3    1    1'//nl), &
                             [character(len=80) ::])
    end subroutine bad_rigid_only_x

    !> x fixed along y = 0 and y at node 2 only: rotation about node 2 is free.
    subroutine bad_rigid_rotation(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'rigid-rotation.dat', &
                             ':9: rigid-body motion not suppressed: rotation', &
                             deck(boundary='    1    3    1    1'//nl// &
                                           '    2'//repeat(' ', 15)//'    1'//nl), &
                             [character(len=80) ::])
    end subroutine bad_rigid_rotation

    subroutine bad_unknown_load_keyword(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'unknown-load.dat', ":12: unknown load 'WIND'", &
                             deck(extra='LOADS'//nl//'WIND'//nl), &
                             [character(len=80) :: 'GRAVITY', 'FORCE', 'PRESSURE'])
    end subroutine bad_unknown_load_keyword

    !> The mesh has no named group.
    subroutine bad_unknown_gravity_group(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'gravity-group.dat', ':12:11-20: field GROUP of GRAVITY', &
                             deck(extra='LOADS'//nl//'GRAVITY   ROCK'//nl), &
                             [character(len=80) :: "found 'ROCK'"])
    end subroutine bad_unknown_gravity_group

    subroutine bad_pressure_face_range(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'pressure-face.dat', ':12:16-20: field FACE of PRESSURE', &
                             deck(extra='LOADS'//nl//'PRESSURE      1    5      10.0'//nl), &
                             [character(len=80) :: '1 to 4', "found '5'"])
    end subroutine bad_pressure_face_range

    !> Element 2 is the triangle 2-3-6; PRESSURE on line 14.
    subroutine bad_pressure_triangle_face3(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'pressure-triangle.dat', &
                             ':14:16-20: field FACE of PRESSURE', &
                             deck(elements='    1    1    2    5    4    1'//nl// &
                                           '    2    2    3    6         1'//nl// &
                                           '    3    2    6    5         1'//nl, &
                                  extra='LOADS'//nl//'PRESSURE      2    3      10.0'//nl), &
                             [character(len=80) :: 'triangle', "found '3'"])
    end subroutine bad_pressure_triangle_face3

    subroutine bad_beyond_column_80(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'column-81.dat', ':4:81-85:', &
                             deck(nodes=std_nodes//'    7'//repeat(' ', 75)//'extra'//nl), &
                             [character(len=80) :: 'column 80', "found 'extra'"])
    end subroutine bad_beyond_column_80

    !> The tab is column 6 of line 2.
    subroutine bad_tab_on_fixed_card(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'tab.dat', ':2:6-6:', &
                             deck(nodes='    1'//achar(9)//'3    1'//nl//node_line_2), &
                             [character(len=80) :: 'tab'])
    end subroutine bad_tab_on_fixed_card

    subroutine bad_units_not_kn_m(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'units.dat', ':2:41-50: field UNITS of CONTROL', &
                             deck(head='CONTROL'//nl//repeat(' ', 40)//'KIP-FT'//nl), &
                             [character(len=80) :: 'KN-M', "found 'KIP-FT'"])
    end subroutine bad_units_not_kn_m

    !> MODEL 2 (axisymmetric) is supported since the stage issue; 3 is no model.
    subroutine bad_model_type(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'model-type.dat', ':2:16-20: field MODEL of CONTROL', &
                             deck(head='CONTROL'//nl//'                   3'//nl), &
                             [character(len=80) :: "found '3'"])
    end subroutine bad_model_type

    !> N2 - N1 = 2 is no multiple of 3.
    subroutine bad_increment_not_divisor(error)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), parameter :: bad_inc = &
            '    4    6    3       0.0       1.0       4.0       1.0'//nl
        call expect_rejected(error, 'increment.dat', ':3:11-15: field INC of NODES', &
                             deck(nodes=node_line_1//bad_inc), &
                             [character(len=80) :: "found '3'"])
    end subroutine bad_increment_not_divisor

    !> Token 'zero' sits in columns 16-19.
    subroutine bad_free_format_bad_real(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'free-real.dat', ':2:16-19: field Y1 of NODES', &
                             deck(nodes='&1, 3, 1, 0.0, zero, 4.0, 0.0'//nl//node_line_2), &
                             [character(len=80) :: "found 'zero'"])
    end subroutine bad_free_format_bad_real

    subroutine bad_pa_not_positive(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'pa.dat', ':2:21-30: field PA of CONTROL', &
                             deck(head='CONTROL'//nl//repeat(' ', 20)//'      -1.0'//nl), &
                             [character(len=80) :: '> 0', "found '-1.0'"])
    end subroutine bad_pa_not_positive

    !> N2 > N1 needs the end point.
    subroutine bad_x2_required(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'x2-required.dat', ':2:36-45: field X2 of NODES', &
                             deck(nodes='    1    3    1       0.0       0.0'//nl//node_line_2), &
                             [character(len=80) ::])
    end subroutine bad_x2_required

    !> IX is 0 or 1.
    subroutine bad_boundary_code(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'boundary-code.dat', ':10:16-20: field IX of BOUNDARY', &
                             deck(boundary='    1    3    1    2    1'//nl), &
                             [character(len=80) :: "found '2'"])
    end subroutine bad_boundary_code

    !> Element 2 was generated by line 5.
    subroutine bad_duplicate_element(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'duplicate-element.dat', &
                             ':6: duplicate element 2 (first defined at line 5)', &
                             deck(elements=std_elements//'    2    1    2    5    4    1'//nl), &
                             [character(len=80) ::])
    end subroutine bad_duplicate_element


    !> 1e999 overflows a double: a field error, not inf (nor SIGFPE under -ffpe-trap).
    subroutine bad_real_overflow(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'overflow.dat', ':8:1-10: field E of MATERIALS 1', &
                             deck(materials='    1ELASTIC'//nl//'     1e999       0.3'//nl), &
                             [character(len=80) :: '1e20', "found '1e999'"])
    end subroutine bad_real_overflow

    !> An indented word that is no keyword is data: E = 'inf' is a bad real on line 8, not
    !> an unknown group (headers are left-justified).
    subroutine bad_indented_word(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'indented.dat', ':8:1-10: field E of MATERIALS 1', &
                             deck(materials='    1ELASTIC'//nl//'       inf       0.3'//nl), &
                             [character(len=80) :: 'a real number', "found 'inf'"])
    end subroutine bad_indented_word

    !> '&1,3,1,0,0,4,0, 99': a token after Y2 (the 7th and last NODES field); '99' sits in
    !> columns 17-18 of line 2.
    subroutine bad_free_extra_field(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'free-extra.dat', ':2:17-18: field after Y2 of NODES', &
                             deck(nodes='&1,3,1,0,0,4,0, 99'//nl//node_line_2), &
                             [character(len=80) :: "found '99'"])
    end subroutine bad_free_extra_field

    !> A card that is only '&' has a blank N1 (required), reported at column 2.
    subroutine bad_lone_ampersand(error)
        type(error_t), allocatable, intent(out) :: error
        call expect_rejected(error, 'lone-ampersand.dat', ':2:2-2: field N1 of NODES', &
                             deck(nodes='&'//nl//std_nodes), [character(len=80) ::])
    end subroutine bad_lone_ampersand

    !> A trailing comma is an empty (default) field, and a free-text LABEL keeps its commas.
    subroutine test_free_trailing(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        call read_text('free-trailing.dat', &
                       deck(nodes='&1,3,1,0,0,4,0,'//nl//node_line_2, &
                            materials='&1, elastic, rockfill, zone 3B'//nl// &
                                      '&20000, 0.3, 20,'//nl), model, error)
        if (allocated(error)) return
        call check(error, model%mesh%x(1, 3), 4.0_dp, 'x of node 3 (generated to X2 = 4)', &
                   abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%materials(1)%label, 'rockfill, zone 3B', 'label with a comma')
        if (allocated(error)) return
        call check(error, model%materials(1)%unit_weight, 20.0_dp, 'GAMMA', abs=0.0_dp)
    end subroutine test_free_trailing
end module test_io_deck
