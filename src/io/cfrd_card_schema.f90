!> The card schema: every data card of the deck (docs/cards.md) declared once, each field
!> with its columns, kind, default, limits and the words of its "expected ..." message.
!> `read_card` (cfrd_card_reader) reads and checks a card against its layout; the group
!> readers (cfrd_deck_*) keep only the checks that need other cards (node and element
!> numbers, groups, materials, surfaces) and the generation. `card_schemas` lists every
!> layout by the name of its table in docs/cards.md, which a test holds against the manual.
module cfrd_card_schema
    use cfrd_kinds, only: dp
    use cfrd_cards, only: field_t, int_field, real_field, text_field, found_value, &
                          found_blank, found_upper, default_pa
    use cfrd_model, only: plane_strain, newtop_zero, solver_midpoint
    implicit none
    private

    public :: card_schema_t, card_schemas
    public :: title_fields, loads_header_fields
    public :: control_fields, effects_fields, errctl_fields, node_fields, element_fields, &
              material_fields, elastic_fields, eb_fields, eb_strength_fields, creep_fields, &
              wetting_fields, goodman_fields, pjoint_fields, plinth_fields, interface_fields, &
              slab_fields, stage_fields, load_stage_fields, &
              water_stage_fields, wet_stage_fields, surface_fields, pair_fields, reservoir_fields, &
              gauge_fields, boundary_fields, gravity_fields, force_fields, pressure_fields

    !> A card layout and where docs/cards.md documents it: the group (its `###` section) and
    !> the card (the table's rows with this number in a `card` column; 0 when none).
    type :: card_schema_t
        character(len=:), allocatable :: name
        character(len=:), allocatable :: group
        integer :: card = 0
        type(field_t), allocatable :: fields(:)
    end type card_schema_t

    real(dp), parameter :: big = huge(1.0_dp), small = tiny(1.0_dp)
    !> Largest coordinate magnitude (m): larger is a mistyped field (a dam is kilometres
    !> wide; UTM northings stay below 1e7 m), and squares of lengths beyond 1e154 overflow.
    real(dp), parameter :: max_coordinate = 1.0e7_dp
    !> Bounds of the creep parameters: values beyond them are mistyped fields (published
    !> laboratory and back-analysed values lie well inside, docs/theory.md section 15).
    real(dp), parameter :: alpha_max = 1.0_dp     !! 1/day: 63 % of the creep in one day
    !> (and of the wetting parameters, docs/theory.md section 16)
    real(dp), parameter :: strain_max = 0.05_dp   !! final creep strains at pa, S/(1-S) = 1
    real(dp), parameter :: exponent_max = 3.0_dp

    character(len=*), parameter :: on_off = 'ON (the default, also blank) or OFF'
    character(len=*), parameter :: a_count = 'a count >= 1 (or blank)'
    character(len=*), parameter :: a_face = 'a face from 1 to 4'

    !> Header cards that carry a value: the TITLE card's title and a LOADS set's name.
    type(field_t), parameter :: title_fields(2) = [field_t('KEYWORD', 1, 10, text_field), &
                                                   field_t('TITLE', 11, 70, text_field)]
    type(field_t), parameter :: loads_header_fields(2) = [ &
        field_t('KEYWORD', 1, 10, text_field), field_t('NAME', 11, 10, text_field)]
    type(field_t), parameter :: control_fields(11) = [ &
        field_t('NNODE', 1, 5, int_field, lo=0.0_dp, expected=a_count, found=found_value), &
        field_t('NELEM', 6, 5, int_field, lo=0.0_dp, expected=a_count, found=found_value), &
        field_t('NMAT', 11, 5, int_field, lo=0.0_dp, expected=a_count, found=found_value), &
        field_t('MODEL', 16, 5, int_field, default=real(plane_strain, dp), lo=1.0_dp, &
                hi=2.0_dp, expected='1 (plane strain) or 2 (axisymmetric)', &
                found=found_value), &
        field_t('PA', 21, 10, real_field, default=101.325_dp, lo=0.0_dp, lo_open=.true., &
                expected='a real > 0'), &
        field_t('GAMMAW', 31, 10, real_field, default=9.81_dp, lo=0.0_dp, lo_open=.true., &
                expected='a real > 0'), &
        field_t('UNITS', 41, 10, text_field, default=1.0_dp, words='KN-M', &
                expected='KN-M (m, kN, kPa) or blank'), &
        field_t('NEWTOP', 51, 5, int_field, default=real(newtop_zero, dp), lo=0.0_dp, &
                hi=1.0_dp, expected='0 (zero a new layer''s displacements when it is '// &
                'complete) or 1 (count them)', found=found_value), &
        field_t('SOLVER', 56, 5, int_field, default=real(solver_midpoint, dp), lo=1.0_dp, &
                hi=3.0_dp, expected='1 (midpoint), 2 (forward Euler) or 3 (Newton)', &
                found=found_value), &
        field_t('TOL', 61, 10, real_field, default=1.0e-6_dp, lo=0.0_dp, lo_open=.true., &
                expected='a real > 0'), &
        field_t('MAXIT', 71, 5, int_field, default=20.0_dp, lo=1.0_dp, &
                expected='a number of iterations >= 1', found=found_value)]
    !> ERRCTL: the error control of the midpoint and Euler increments (issue 21).
    type(field_t), parameter :: errctl_fields(3) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('ERRTOL', 11, 10, real_field, default=5.0e-3_dp, lo=0.0_dp, hi=1.0_dp, &
                expected='a real with 0 <= ERRTOL <= 1 (0: no error control)'), &
        field_t('DEPTH', 21, 5, int_field, default=8.0_dp, lo=0.0_dp, hi=20.0_dp, &
                expected='a number of halvings with 0 <= DEPTH <= 20', found=found_value)]
    !> EFFECTS: each switch's first word (blank too) is the effect on (value 1).
    type(field_t), parameter :: effects_fields(9) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('ROCKFILL', 11, 10, text_field, default=1.0_dp, words='NONLINEAR LINEAR', &
                expected='NONLINEAR (the default, also blank) or LINEAR', found=found_upper), &
        field_t('UNLOAD', 21, 10, text_field, default=1.0_dp, words='ON OFF', &
                expected=on_off, found=found_upper), &
        field_t('WATER', 31, 10, text_field, default=1.0_dp, words='ON OFF', &
                expected=on_off, found=found_upper), &
        field_t('INTERFACE', 41, 10, text_field, default=1.0_dp, words='DECK BONDED', &
                expected='DECK (the default, also blank) or BONDED', found=found_upper), &
        field_t('FRICTION', 51, 10, text_field, default=1.0_dp, words='ON OFF', &
                expected=on_off, found=found_upper), &
        field_t('SLIP', 61, 10, text_field, default=1.0_dp, words='LARGE SMALL', &
                expected='LARGE (the default, also blank) or SMALL', found=found_upper), &
        field_t('PHASES', 71, 10, text_field, default=1.0_dp, words='ON OFF', &
                expected=on_off, found=found_upper), &
        field_t('CREEP', 81, 10, text_field, default=1.0_dp, words='ON OFF', &
                expected=on_off, found=found_upper)]

    ! N1, N2, INC of a node range: the numbers are checked against the nodes by get_range.
    character(len=*), parameter :: an_increment = 'an increment >= 1'
    character(len=*), parameter :: a_coordinate = 'a coordinate of magnitude at most 1e7 (m)'
    type(field_t), parameter :: node_fields(7) = [ &
        field_t('N1', 1, 5, int_field), &
        field_t('N2', 6, 5, int_field, default_from=1), &
        field_t('INC', 11, 5, int_field, default=1.0_dp, lo=1.0_dp, expected=an_increment), &
        field_t('X1', 16, 10, real_field, lo=-max_coordinate, hi=max_coordinate, &
                expected=a_coordinate), &
        field_t('Y1', 26, 10, real_field, lo=-max_coordinate, hi=max_coordinate, &
                expected=a_coordinate), &
        field_t('X2', 36, 10, real_field, lo=-max_coordinate, hi=max_coordinate, &
                expected=a_coordinate), &
        field_t('Y2', 46, 10, real_field, lo=-max_coordinate, hi=max_coordinate, &
                expected=a_coordinate)]

    type(field_t), parameter :: element_fields(10) = [ &
        field_t('NE', 1, 5, int_field), &
        field_t('I', 6, 5, int_field), &
        field_t('J', 11, 5, int_field), &
        field_t('K', 16, 5, int_field), &
        field_t('L', 21, 5, int_field), &
        field_t('MAT', 26, 5, int_field), &
        field_t('NGEN', 31, 5, int_field), &
        field_t('NINC', 36, 5, int_field, default=1.0_dp), &
        field_t('GROUP', 41, 10, text_field), &
        field_t('TYPE', 51, 10, text_field, default=1.0_dp, words='Q4 Q4S', &
                expected='an element type: Q4 (blank) or Q4S (assumed shear strain, for '// &
                'slabs in bending)')]

    type(field_t), parameter :: material_fields(3) = [ &
        field_t('M', 1, 5, int_field), &
        field_t('LAW', 6, 10, text_field, words='ELASTIC EB GOODMAN PJOINT', &
                expected='a material law: ELASTIC, EB, GOODMAN or PJOINT', &
                found=found_upper), &
        field_t('LABEL', 16, 65, text_field)]
    !> ELASTIC: E and NU blank fail their checks, quoted as '(blank)'.
    !> FT blank: no tensile strength given, no crack-risk ratio (docs/theory.md section 13).
    type(field_t), parameter :: elastic_fields(4) = [ &
        field_t('E', 1, 10, real_field, lo=0.0_dp, lo_open=.true., &
                expected='a real > 0 (kPa)', found=found_blank), &
        field_t('NU', 11, 10, real_field, default=-1.0_dp, lo=0.0_dp, hi=0.5_dp, &
                hi_open=.true., expected='a real with 0 <= NU < 0.5', found=found_blank), &
        field_t('GAMMA', 21, 10, real_field, lo=0.0_dp, expected='a real >= 0 (kN/m3)', &
                found=found_blank), &
        field_t('FT', 31, 10, real_field, lo=0.0_dp, expected='a real >= 0 (kPa)', &
                found=found_blank)]
    !> EB card 2; Kur blank: 2 K, a common rockfill value (reference file, [choice]).
    type(field_t), parameter :: eb_fields(7) = [ &
        field_t('GAMMA', 1, 10, real_field, lo=0.0_dp, expected='a real >= 0 (kN/m3)'), &
        field_t('K', 11, 10, real_field, required=.true., lo=small, expected='a real > 0'), &
        field_t('N', 21, 10, real_field, required=.true., lo=0.0_dp, hi=0.999_dp, &
                expected='a real with 0 <= N <= 0.999'), &
        field_t('RF', 31, 10, real_field, required=.true., lo=small, hi=1.0_dp, &
                expected='a real with 0 < RF <= 1'), &
        field_t('KB', 41, 10, real_field, required=.true., lo=small, expected='a real > 0'), &
        field_t('M', 51, 10, real_field, required=.true., lo=-0.999_dp, hi=0.999_dp, &
                expected='a real with -0.999 <= M <= 0.999'), &
        field_t('KUR', 61, 10, real_field, default_from=2, default_scale=2.0_dp, lo=small, &
                expected='a real > 0 (blank = 2 K)')]
    !> EB card 3; the floor on sigma3 for the moduli, blank: 0.1 pa (docs/theory.md s. 8).
    type(field_t), parameter :: eb_strength_fields(4) = [ &
        field_t('PHI0', 1, 10, real_field, required=.true., lo=small, hi=89.0_dp, &
                expected='an angle in degrees, 0 < PHI0 <= 89'), &
        field_t('DPHI', 11, 10, real_field, lo=0.0_dp, hi=89.0_dp, &
                expected='an angle in degrees, 0 <= DPHI <= 89'), &
        field_t('C', 21, 10, real_field, lo=0.0_dp, expected='a real >= 0 (kPa)'), &
        field_t('SIG3MIN', 31, 10, real_field, default_from=default_pa, &
                default_scale=0.1_dp, lo=small, expected='a real > 0 (kPa, blank = 0.1 PA)')]
    !> The CREEP card that may follow an EB material's two parameter cards.
    type(field_t), parameter :: creep_fields(6) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('ALPHA', 11, 10, real_field, required=.true., lo=0.0_dp, lo_open=.true., &
                hi=alpha_max, expected='a real with 0 < ALPHA <= 1 (1/day)'), &
        field_t('B', 21, 10, real_field, required=.true., lo=0.0_dp, hi=strain_max, &
                expected='a real with 0 <= B <= 0.05'), &
        field_t('MC', 31, 10, real_field, required=.true., lo=0.0_dp, lo_open=.true., &
                hi=exponent_max, expected='a real with 0 < MC <= 3'), &
        field_t('D', 41, 10, real_field, required=.true., lo=0.0_dp, hi=strain_max, &
                expected='a real with 0 <= D <= 0.05'), &
        field_t('L', 51, 10, real_field, required=.true., lo=0.0_dp, lo_open=.true., &
                hi=exponent_max, expected='a real with 0 < L <= 3')]
    !> The WETTING card that may follow an EB material's two parameter cards or its CREEP
    !> card (Shen's wetting collapse).
    type(field_t), parameter :: wetting_fields(4) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('CW', 11, 10, real_field, required=.true., lo=0.0_dp, hi=strain_max, &
                expected='a real with 0 <= CW <= 0.05'), &
        field_t('NW', 21, 10, real_field, required=.true., lo=0.0_dp, lo_open=.true., &
                hi=exponent_max, expected='a real with 0 < NW <= 3'), &
        field_t('DW', 31, 10, real_field, required=.true., lo=0.0_dp, hi=strain_max, &
                expected='a real with 0 <= DW <= 0.05')]
    !> GOODMAN card 2; SNMIN, the floor on the compressive normal stress in ks, blank:
    !> 0.1 pa, as SIG3MIN of EB.
    type(field_t), parameter :: goodman_fields(8) = [ &
        field_t('KNC', 1, 10, real_field, required=.true., lo=small, &
                expected='a real > 0 (kPa/m)'), &
        field_t('KNT', 11, 10, real_field, required=.true., lo=small, &
                expected='a real > 0 (kPa/m)'), &
        field_t('K1', 21, 10, real_field, required=.true., lo=small, expected='a real > 0'), &
        field_t('N1', 31, 10, real_field, required=.true., lo=0.0_dp, hi=0.999_dp, &
                expected='a real with 0 <= N1 <= 0.999'), &
        field_t('RF1', 41, 10, real_field, required=.true., lo=0.0_dp, hi=1.0_dp, &
                expected='a real with 0 <= RF1 <= 1'), &
        field_t('PHI', 51, 10, real_field, required=.true., lo=small, hi=89.0_dp, &
                expected='an angle in degrees, 0 < PHI <= 89'), &
        field_t('SNMIN', 61, 10, real_field, default_from=default_pa, default_scale=0.1_dp, &
                lo=small, expected='a real > 0 (kPa, blank = 0.1 PA)'), &
        field_t('CUTOFF', 71, 5, int_field, lo=0.0_dp, hi=1.0_dp, &
                expected='0 (tension carried with KNT) or 1 (tension cut-off)', &
                found=found_value)]

    !> PJOINT card 2: the perimetric joint's stiffnesses (docs/theory.md section 12).
    type(field_t), parameter :: pjoint_fields(3) = [ &
        field_t('KNC', 1, 10, real_field, required=.true., lo=small, &
                expected='a real > 0 (kPa/m)'), &
        field_t('KNT', 11, 10, real_field, required=.true., lo=small, &
                expected='a real > 0 (kPa/m)'), &
        field_t('KS', 21, 10, real_field, required=.true., lo=small, &
                expected='a real > 0 (kPa/m)')]

    type(field_t), parameter :: interface_fields(10) = [ &
        field_t('LINE', 1, 5, int_field, lo=1.0_dp, expected='an interface line number >= 1'), &
        field_t('NB', 6, 5, int_field), &
        field_t('NT', 11, 5, int_field), &
        field_t('NGEN', 16, 5, int_field, lo=0.0_dp, expected='a count >= 0'), &
        field_t('INCB', 21, 5, int_field, default=1.0_dp), &
        field_t('INCT', 26, 5, int_field, default=1.0_dp), &
        field_t('MAT', 31, 5, int_field), &
        field_t('TYPE', 36, 10, text_field, words='JOINT THIN', &
                expected='an interface type: JOINT or THIN', found=found_upper), &
        field_t('RULE', 46, 10, text_field), &
        field_t('GROUP', 56, 10, text_field)]
    type(field_t), parameter :: slab_fields(1) = [field_t('GROUP', 11, 10, text_field)]
    type(field_t), parameter :: plinth_fields(1) = [field_t('GROUP', 11, 10, text_field)]

    type(field_t), parameter :: stage_ninc = field_t('NINC', 21, 5, int_field, &
        default=1.0_dp, lo=1.0_dp, hi=100000.0_dp, &
        expected='a number of increments from 1 to 100000')
    type(field_t), parameter :: stage_fields(5) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('GROUP', 11, 10, text_field), &
        stage_ninc, &
        field_t('DATE', 26, 10, text_field), &
        field_t('LABEL', 36, 45, text_field)]
    !> A LOAD stage card: the same columns, field 2 naming a load set.
    type(field_t), parameter :: load_stage_fields(5) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('SET', 11, 10, text_field), &
        stage_ninc, &
        field_t('DATE', 26, 10, text_field), &
        field_t('LABEL', 36, 45, text_field)]
    !> A WATER stage card: field 2 is the reservoir level to reach.
    type(field_t), parameter :: water_stage_fields(5) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('LEVEL', 11, 10, real_field, required=.true., &
                expected='the reservoir level to reach (m)'), &
        stage_ninc, &
        field_t('DATE', 26, 10, text_field), &
        field_t('LABEL', 36, 45, text_field)]

    !> A WET stage card: field 2 is the level below which elements are wetted; blank:
    !> every element (an infinite level).
    type(field_t), parameter :: wet_stage_fields(5) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('LEVEL', 11, 10, real_field, default=big), &
        stage_ninc, &
        field_t('DATE', 26, 10, text_field), &
        field_t('LABEL', 36, 45, text_field)]

    type(field_t), parameter :: surface_fields(6) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('NAME', 11, 10, text_field, required=.true., expected='a surface name'), &
        field_t('ELEM', 21, 5, int_field), &
        field_t('FACE', 26, 5, int_field, lo=1.0_dp, hi=4.0_dp, expected=a_face), &
        field_t('NGEN', 31, 5, int_field, lo=0.0_dp, expected='an integer >= 0'), &
        field_t('INC', 36, 5, int_field, default=1.0_dp)]
    type(field_t), parameter :: pair_fields(9) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('SLAVE', 11, 10, text_field), &
        field_t('MASTER', 21, 10, text_field), &
        field_t('MU', 31, 10, real_field, lo=0.0_dp, expected='a real >= 0'), &
        field_t('TOL', 41, 10, real_field, lo=0.0_dp, expected='a real >= 0 (m)'), &
        field_t('SCHEME', 51, 10, text_field, default=1.0_dp, words='MORTAR NTS', &
                expected='MORTAR (segment-to-segment) or NTS (node-to-segment)'), &
        field_t('SEARCH', 61, 10, text_field, default=1.0_dp, words='LINEAR RPIM', &
                expected='LINEAR (piecewise-linear master surface) or RPIM (radial point '// &
                'interpolation)'), &
        field_t('CAST', 71, 5, int_field, lo=0.0_dp, hi=1.0_dp, expected='0 or 1 (1: '// &
                'cast in place, the gap at placement counts as closed)'), &
        field_t('ROLES', 76, 5, text_field, default=1.0_dp, words='AUTO ASIS', &
                expected='AUTO (a much finer slave becomes the master) or ASIS')]

    type(field_t), parameter :: reservoir_fields(3) = [ &
        field_t('ELEM', 1, 5, int_field), &
        field_t('FACE', 6, 5, int_field, lo=1.0_dp, hi=4.0_dp, expected=a_face), &
        field_t('COVER', 11, 10, text_field)]
    type(field_t), parameter :: gauge_fields(3) = [ &
        field_t('NODE', 1, 5, int_field), &
        field_t('NAME', 6, 10, text_field, required=.true., expected='a gauge name'), &
        field_t('LABEL', 16, 65, text_field)]

    character(len=*), parameter :: a_code = '0 (free) or 1 (prescribed)'
    type(field_t), parameter :: boundary_fields(7) = [ &
        field_t('N1', 1, 5, int_field), &
        field_t('N2', 6, 5, int_field, default_from=1), &
        field_t('INC', 11, 5, int_field, default=1.0_dp, lo=1.0_dp, expected=an_increment), &
        field_t('IX', 16, 5, int_field, lo=0.0_dp, hi=1.0_dp, expected=a_code, &
                found=found_value), &
        field_t('IY', 21, 5, int_field, lo=0.0_dp, hi=1.0_dp, expected=a_code, &
                found=found_value), &
        field_t('UX', 26, 10, real_field), &
        field_t('UY', 36, 10, real_field)]
    type(field_t), parameter :: gravity_fields(4) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('GROUP', 11, 10, text_field), &
        field_t('AX', 21, 10, real_field), &
        field_t('AY', 31, 10, real_field, default=-1.0_dp)]
    type(field_t), parameter :: force_fields(6) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('N1', 11, 5, int_field), &
        field_t('N2', 16, 5, int_field, default_from=2), &
        field_t('INC', 21, 5, int_field, default=1.0_dp, lo=1.0_dp, expected=an_increment), &
        field_t('FX', 26, 10, real_field), &
        field_t('FY', 36, 10, real_field)]
    type(field_t), parameter :: pressure_fields(5) = [ &
        field_t('KEYWORD', 1, 10, text_field), &
        field_t('ELEM', 11, 5, int_field), &
        field_t('FACE', 16, 5, int_field, lo=1.0_dp, hi=4.0_dp, expected=a_face), &
        field_t('P1', 21, 10, real_field), &
        field_t('P2', 31, 10, real_field, default_from=4)]

contains

    !> Every card layout, named as in docs/cards.md (group section, card number).
    function card_schemas() result(cards)
        type(card_schema_t), allocatable :: cards(:)
        allocate (cards(30))
        call set(1, 'CONTROL', 'CONTROL', 0, control_fields)
        call set(2, 'CONTROL EFFECTS', 'CONTROL', 0, effects_fields)
        call set(30, 'CONTROL ERRCTL', 'CONTROL', 0, errctl_fields)
        call set(3, 'NODES', 'NODES', 0, node_fields)
        call set(4, 'ELEMENTS', 'ELEMENTS', 0, element_fields)
        call set(5, 'MATERIALS card 1', 'MATERIALS', 0, material_fields)
        call set(6, 'MATERIALS ELASTIC card 2', 'MATERIALS', 0, elastic_fields)
        call set(7, 'MATERIALS EB card 2', 'MATERIALS', 2, eb_fields)
        call set(8, 'MATERIALS EB card 3', 'MATERIALS', 3, eb_strength_fields)
        call set(9, 'MATERIALS CREEP', 'MATERIALS', 0, creep_fields)
        call set(10, 'MATERIALS WETTING', 'MATERIALS', 0, wetting_fields)
        call set(11, 'MATERIALS GOODMAN card 2', 'MATERIALS', 0, goodman_fields)
        call set(12, 'BOUNDARY', 'BOUNDARY', 0, boundary_fields)
        call set(13, 'LOADS GRAVITY', 'LOADS', 0, gravity_fields)
        call set(14, 'LOADS FORCE', 'LOADS', 0, force_fields)
        call set(15, 'LOADS PRESSURE', 'LOADS', 0, pressure_fields)
        call set(16, 'RESERVOIR', 'RESERVOIR', 0, reservoir_fields)
        call set(17, 'GAUGES', 'GAUGES', 0, gauge_fields)
        call set(18, 'INTERFACE', 'INTERFACE', 0, interface_fields)
        call set(19, 'SLAB', 'SLAB', 0, slab_fields)
        call set(20, 'CONTACT SURFACE', 'CONTACT', 0, surface_fields)
        call set(21, 'CONTACT PAIR', 'CONTACT', 0, pair_fields)
        call set(22, 'STAGES FILL', 'STAGES', 0, stage_fields)
        call set(23, 'STAGES LOAD', 'STAGES', 0, load_stage_fields)
        call set(24, 'STAGES WATER', 'STAGES', 0, water_stage_fields)
        call set(25, 'STAGES WET', 'STAGES', 0, wet_stage_fields)
        call set(26, 'TITLE', 'TITLE', 0, title_fields)
        call set(27, 'LOADS header', 'LOADS', 0, loads_header_fields)
        call set(28, 'MATERIALS PJOINT card 2', 'MATERIALS', 0, pjoint_fields)
        call set(29, 'PLINTH', 'PLINTH', 0, plinth_fields)
    contains
        subroutine set(i, name, group, card, fields)
            integer, intent(in) :: i, card
            character(len=*), intent(in) :: name, group
            type(field_t), intent(in) :: fields(:)
            cards(i)%name = name
            cards(i)%group = group
            cards(i)%card = card
            cards(i)%fields = fields
        end subroutine set
    end function card_schemas
end module cfrd_card_schema
