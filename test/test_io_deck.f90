!> Tests of the deck reader on valid decks: every value checked against the card manual
!> (docs/cards.md) worked out by hand. The bad decks are checked through the command line
!> (test/bad_decks, tools/run_tests.sh); a few are repeated here at library level to show
!> that the reader returns an input error rather than stopping.
module test_io_deck
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, input_error
    use cfrd_testing, only: unittest_t, new_unittest, check, fail
    use cfrd_model, only: model_t, all_groups
    use cfrd_deck, only: read_deck
    implicit none
    private

    public :: collect_io_deck

    character(len=*), parameter :: dir = 'build/test-decks/'
    character(len=*), parameter :: nl = new_line('a')

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
                new_unittest('fortran_real_syntax', test_real_syntax), &
                new_unittest('bad_deck_is_an_input_error', test_bad_deck_error), &
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
        call check(error, model%load_sets(1)%nodal_force(1, 6), 11.5_dp, 'FX at node 6 (10 + 1.5)', &
                   abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%load_sets(1)%nodal_force(2, 4), -5.0_dp, 'FY at node 4', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%load_sets(1)%nodal_force(2, 5), 0.0_dp, 'node 5 skipped by INC', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, model%load_sets(1)%pressures(1)%face, 2, 'face')
        if (allocated(error)) return
        call check(error, model%load_sets(1)%pressures(1)%p2, 30.0_dp, 'P2 defaults to P1', abs=0.0_dp)
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

    !> F10.0 fields in Fortran syntax: '2.0D4', '20000', '.2E5' are all 20000; '.25' is 0.25.
    subroutine test_real_syntax(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        character(len=10), parameter :: spellings(3) = ['     2.0D4', '     20000', &
                                                        '      .2E5']
        integer :: i
        do i = 1, 3
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
end module test_io_deck
