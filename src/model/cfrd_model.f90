!> The analysis model as parameters: mesh, materials, boundary conditions and loads.
!> Built by the deck reader (`io/`), read by the analysis; it never changes during a run.
!> Node, element and material numbers are their positions in the arrays (1..n): the deck
!> reader insists on complete, consecutive numbering, as the legacy codes did.
module cfrd_model
    use cfrd_kinds, only: dp
    use cfrd_linear_solver, only: linear_solver_auto
    implicit none
    private

    public :: model_t, mesh_t, material_t, gravity_load_t, pressure_load_t, load_set_t
    public :: stage_t, stage_fill, stage_load, stage_reset, stage_water, stage_wait
    public :: stage_kind_name, no_date, has_creep, has_wetting, stage_wet, fill_active
    public :: wet_face_t, gauge_t, dry_level
    public :: plane_strain, axisymmetric, law_elastic, law_duncan_eb, law_goodman, all_groups
    public :: law_pjoint, is_joint_law
    public :: elem_quad4, elem_quad4_shear, elem_joint_gauss, elem_joint_lobatto, is_joint_kind
    public :: interface_element_t, method_joint, method_thin, method_name
    public :: newtop_count, newtop_zero, solver_midpoint, solver_euler, solver_newton
    public :: law_name, effects_t
    public :: contact_surface_t, contact_pair_t, scheme_mortar, scheme_nts, search_linear, &
              search_rpim, scheme_name, search_name

    !> Analysis types (CONTROL card, field MODEL).
    integer, parameter :: plane_strain = 1
    integer, parameter :: axisymmetric = 2

    !> Material laws (MATERIALS card, field LAW).
    integer, parameter :: law_elastic = 1
    integer, parameter :: law_duncan_eb = 2
    integer, parameter :: law_goodman = 3    !! interface law of zero-thickness joints
    integer, parameter :: law_pjoint = 4     !! perimetric joint: bilinear normal, linear shear

    !> Stage kinds (STAGES cards).
    integer, parameter :: stage_fill = 1    !! activate an element group under its own weight
    integer, parameter :: stage_load = 2    !! apply a load set
    integer, parameter :: stage_reset = 3   !! zero the displacements, keep the stresses
    integer, parameter :: stage_water = 4   !! raise or lower the reservoir to a level
    integer, parameter :: stage_wait = 5    !! let time pass with no load (creep)
    integer, parameter :: stage_wet = 6     !! wet the rockfill below a level (collapse)

    !> The day number of a stage without a date (or with a free-text one): no time passes.
    real(dp), parameter :: no_date = -huge(1.0_dp)

    !> The reservoir level before any WATER stage: below everything (no water).
    real(dp), parameter :: dry_level = -huge(1.0_dp)

    !> How the displacement of a new layer's own nodes during its placement counts
    !> (CONTROL field NEWTOP, docs/theory.md section 9).
    integer, parameter :: newtop_zero = 0   !! zeroed when the layer is complete (default)
    integer, parameter :: newtop_count = 1  !! counted

    !> Nonlinear solution per increment (CONTROL field SOLVER).
    integer, parameter :: solver_midpoint = 1  !! midpoint stiffness (modified Euler)
    integer, parameter :: solver_euler = 2     !! forward Euler (tangent at the start)
    integer, parameter :: solver_newton = 3    !! midpoint predictor, then Newton iterations

    !> Element kinds; the element factory maps each to an element implementation.
    integer, parameter :: elem_quad4 = 1
    integer, parameter :: elem_joint_gauss = 2     !! Goodman joint, 2-point Gauss rule
    integer, parameter :: elem_joint_lobatto = 3   !! Goodman joint, 2-point Newton-Cotes rule
    !> 4-node quad with the natural shear strain of its centre (ELEMENTS type Q4S): no
    !> parasitic shear in bending, for the face slab
    integer, parameter :: elem_quad4_shear = 4

    !> Interface methods (INTERFACE cards, field TYPE).
    integer, parameter :: method_joint = 1   !! zero-thickness Goodman joint elements
    integer, parameter :: method_thin = 2    !! thin-layer solid elements (quads)

    !> Contact discretisation (CONTACT PAIR cards, field SCHEME).
    integer, parameter :: scheme_mortar = 1  !! segment-to-segment (mortar), dual multipliers
    integer, parameter :: scheme_nts = 2     !! node-to-segment, for comparison
    !> Contact search (field SEARCH): how the master surface is interpolated.
    integer, parameter :: search_linear = 1  !! piecewise-linear (the element faces)
    integer, parameter :: search_rpim = 2    !! radial point interpolation (paper Step 3)

    !> Group index meaning "every element" in a gravity load.
    integer, parameter :: all_groups = 0

    !> One material: its law and the parameters that law reads.
    type :: material_t
        integer :: law = law_elastic
        character(len=:), allocatable :: label
        real(dp) :: unit_weight = 0.0_dp     !! kN/m3, for gravity loads
        real(dp) :: youngs_modulus = 0.0_dp  !! kPa (ELASTIC)
        real(dp) :: poisson_ratio = 0.0_dp   !! - (ELASTIC)
        !> ELASTIC: tensile strength f_t (kPa) for the slab's crack-risk ratio; 0: not given
        real(dp) :: tensile_strength = 0.0_dp
        !> Duncan-Chang E-B parameters (law EB): K, n, Rf, Kb, m, phi0 (deg), dphi (deg),
        !> c (kPa), Kur, floor on sigma3 (kPa)
        real(dp) :: k_modulus = 0.0_dp, n_exponent = 0.0_dp, failure_ratio = 0.0_dp
        real(dp) :: k_bulk = 0.0_dp, m_exponent = 0.0_dp
        real(dp) :: phi0 = 0.0_dp, dphi = 0.0_dp, cohesion = 0.0_dp
        real(dp) :: k_unload = 0.0_dp, sigma3_floor = 0.0_dp
        !> Goodman joint (law GOODMAN, paper eqs. 6-7): normal stiffness in compression and
        !> in tension (kPa/m), k1, n1, Rf1, friction angle phi (deg), floor on the
        !> compressive normal stress in ks (kPa), gamma_w (kN/m3, from CONTROL), tension
        !> cut-off (an open joint carries no stress)
        real(dp) :: kn_compression = 0.0_dp, kn_tension = 0.0_dp
        real(dp) :: k1 = 0.0_dp, n1 = 0.0_dp, rf1 = 0.0_dp, phi = 0.0_dp
        real(dp) :: sigma_n_floor = 0.0_dp, gamma_w = 9.81_dp
        logical :: tension_cutoff = .false.
        !> Perimetric joint (law PJOINT): kn_compression, kn_tension above and the linear
        !> shear stiffness ks (kPa/m)
        real(dp) :: ks_joint = 0.0_dp
        !> E-B: the unload-reload modulus where the stress state falls below its past
        !> maximum (off by the EFFECTS card: the loading modulus always, no history kept)
        logical :: unload = .true.
        !> E-B: time-dependent deformation (the CREEP card, docs/theory.md section 15):
        !> decay rate alpha (1/day), final volumetric strain b and exponent mc of sigma3/pa,
        !> final shear strain d and exponent l of S/(1 - S)
        logical :: creep = .false.
        real(dp) :: creep_alpha = 0.0_dp, creep_b = 0.0_dp, creep_mc = 0.0_dp
        real(dp) :: creep_d = 0.0_dp, creep_l = 0.0_dp
        !> E-B: wetting collapse (the WETTING card, docs/theory.md section 16): final
        !> volumetric strain cw and exponent nw of sigma3/pa, final shear strain dw times
        !> S/(1 - S), taken when a WET stage wets the element
        logical :: wetting = .false.
        real(dp) :: wet_c = 0.0_dp, wet_n = 0.0_dp, wet_d = 0.0_dp
    end type material_t

    !> One element of an interface line (INTERFACE cards): a joint or a thin-layer quad
    !> between the pairs k and k+1 of bottom (cushion side) and top (slab side) nodes,
    !> conn = (bottom k, bottom k+1, top k+1, top k).
    type :: interface_element_t
        integer :: element = 0      !! element number in the mesh
        integer :: line = 0         !! interface line number
        integer :: method = method_joint
    end type interface_element_t

    !> A contact surface (CONTACT SURFACE cards): element faces, face k running from node k
    !> to node k+1 of the element (counter-clockwise, so the body lies on its left).
    type :: contact_surface_t
        character(len=10) :: name = ''
        integer, allocatable :: element(:)
        integer, allocatable :: face(:)
    end type contact_surface_t

    !> A contact pair (a CONTACT PAIR card): the slave surface's nodes carry the Lagrange
    !> multipliers (contact tractions), the master surface is searched (docs/theory.md
    !> section 14).
    type :: contact_pair_t
        integer :: slave = 0                 !! index into model%surfaces
        integer :: master = 0                !! index into model%surfaces
        real(dp) :: friction = 0.0_dp        !! Coulomb coefficient mu (eq. 16)
        real(dp) :: tolerance = 0.0_dp       !! closure distance TOL, m (eq. 15)
        integer :: scheme = scheme_mortar
        integer :: search = search_linear
        !> Cast in place: the gap a slave node has when it is placed counts as closed
        !> (a slab cast on the cushion starts in contact wherever it is placed).
        logical :: cast = .false.
        !> ROLES ASIS: the roles as the card gives them, however fine the slave
        logical :: roles_asis = .false.
        !> The card's SLAVE is much finer than its MASTER and the roles were swapped
        !> (cfrd_contact_roles): `slave` and `master` above are the roles as solved
        logical :: swapped = .false.
        integer :: line = 0                  !! deck line, for messages
    end type contact_pair_t

    !> Nodes and elements. Triangles are degenerate quads with conn(4,e) == conn(3,e).
    type :: mesh_t
        integer :: nnode = 0
        integer :: nelem = 0
        real(dp), allocatable :: x(:, :)        !! (2, nnode) coordinates x, y in m
        integer, allocatable :: conn(:, :)      !! (4, nelem) nodes, counter-clockwise
        integer, allocatable :: kind(:)         !! (nelem) element kind, elem_quad4, ...
        integer, allocatable :: material(:)     !! (nelem) material number
        integer, allocatable :: group(:)        !! (nelem) index into group_name, 0 = none
        character(len=10), allocatable :: group_name(:)  !! named element groups
    end type mesh_t

    !> Gravity on a group of elements: body force per volume = unit weight * (ax, ay).
    type :: gravity_load_t
        integer :: group = all_groups           !! index into mesh%group_name, or all_groups
        real(dp) :: ax = 0.0_dp
        real(dp) :: ay = -1.0_dp
    end type gravity_load_t

    !> Normal pressure on face `face` (1..4: from node face to node face+1) of an element,
    !> varying linearly from p1 at the face's first node to p2 at its second; positive
    !> pressure pushes into the element.
    type :: pressure_load_t
        integer :: element = 0
        integer :: face = 0
        real(dp) :: p1 = 0.0_dp   !! kPa
        real(dp) :: p2 = 0.0_dp   !! kPa
    end type pressure_load_t

    !> A named set of loads (a LOADS group); set 1 is the unnamed default set.
    type :: load_set_t
        character(len=10) :: name = ''
        real(dp), allocatable :: nodal_force(:, :)  !! (2, nnode) kN/m
        type(gravity_load_t), allocatable :: gravity(:)
        type(pressure_load_t), allocatable :: pressures(:)
    end type load_set_t

    !> An element face the reservoir wets (a RESERVOIR card): hydrostatic pressure
    !> gamma_w (level - y) acts on its part below the level while the element is active
    !> and, if `cover` names a group, until that group is placed (a slab phase that covers
    !> a cushion face).
    type :: wet_face_t
        integer :: element = 0
        integer :: face = 0           !! 1..4, as for PRESSURE
        integer :: cover = 0          !! index into mesh%group_name, 0 = never covered
    end type wet_face_t

    !> A named observation point at a node (a GAUGES card), whose displacement history is
    !> tabulated per stage.
    type :: gauge_t
        character(len=10) :: name = ''
        integer :: node = 0
        character(len=:), allocatable :: label
    end type gauge_t

    !> One construction or loading stage (a STAGES card).
    type :: stage_t
        integer :: kind = stage_load
        integer :: group = 0          !! element group activated (FILL)
        integer :: load_set = 1       !! load set applied (LOAD)
        !> reservoir level reached (WATER), or the level below which a WET stage wets, m
        real(dp) :: level = 0.0_dp
        integer :: increments = 1
        character(len=:), allocatable :: label
        character(len=:), allocatable :: date   !! calendar date as written, may be ''
        !> the date as a day number (cfrd_dates), no_date for a blank or free-text date;
        !> a stage spans the time from the last dated stage before it to its own date
        real(dp) :: day = no_date
        integer :: line = 0           !! deck line, for messages
    end type stage_t

    !> The effects a deck asks for (the EFFECTS card of CONTROL, docs/cards.md); all on by
    !> default. The deck reader applies them to the model (cfrd_effects): what is off is not
    !> assembled, searched or stored.
    type :: effects_t
        logical :: nonlinear_rockfill = .true.  !! E-B laws (off: linear, moduli at pa)
        logical :: unload = .true.              !! E-B unload-reload modulus Kur
        logical :: water = .true.               !! water pressure on the RESERVOIR faces
        logical :: interface = .true.           !! INTERFACE joints (off: bonded)
        logical :: friction = .true.            !! Coulomb friction of the CONTACT pairs
        logical :: large_slip = .true.          !! contact geometry at every increment
        logical :: phases = .true.              !! slab cast in its phases (off: at once)
        logical :: creep = .true.               !! CREEP cards of the EB materials
        integer :: line = 0                     !! deck line of the EFFECTS card, 0 = none
    end type effects_t

    !> Everything a deck says.
    type :: model_t
        character(len=:), allocatable :: deck_file   !! the file it was read from
        character(len=:), allocatable :: deck_text   !! the deck as read, lines joined by LF
        character(len=:), allocatable :: title
        integer :: analysis = plane_strain
        real(dp) :: pa = 101.325_dp      !! atmospheric pressure, kPa
        real(dp) :: gamma_w = 9.81_dp    !! unit weight of water, kN/m3
        character(len=:), allocatable :: units      !! 'KN-M'
        type(mesh_t) :: mesh
        type(material_t), allocatable :: materials(:)
        logical, allocatable :: fixed(:, :)         !! (2, nnode) dof is prescribed
        real(dp), allocatable :: prescribed(:, :)   !! (2, nnode) its value, m
        type(load_set_t), allocatable :: load_sets(:)
        !> Stages in order; a deck without STAGES has one LOAD stage of the default set with
        !> every element active.
        type(stage_t), allocatable :: stages(:)
        type(wet_face_t), allocatable :: wet_faces(:)   !! RESERVOIR cards
        type(gauge_t), allocatable :: gauges(:)         !! GAUGES cards
        !> INTERFACE cards: the interface elements in line order
        type(interface_element_t), allocatable :: interfaces(:)
        integer, allocatable :: slab_groups(:)          !! SLAB cards: element groups
        integer, allocatable :: plinth_groups(:)        !! PLINTH cards: element groups
        !> CONTACT cards: surfaces and the pairs between them (none: no contact at all)
        type(contact_surface_t), allocatable :: surfaces(:)
        type(contact_pair_t), allocatable :: contact_pairs(:)
        !> Warnings of the deck reader (the run goes on; printed and listed)
        character(len=300), allocatable :: warnings(:)
        integer :: newtop = newtop_zero
        integer :: solver = solver_midpoint
        real(dp) :: tolerance = 1.0e-6_dp     !! Newton: residual / load, SOLVER = 3
        integer :: max_iterations = 20        !! Newton iterations per increment
        !> Midpoint / Euler error control (CONTROL fields ERRTOL, DEPTH): an increment whose
        !> residual / load exceeds ERRTOL is halved and redone, at most DEPTH halvings below
        !> the nominal increment (docs/theory.md section 9); ERRTOL = 0: no control.
        real(dp) :: error_tolerance = 5.0e-3_dp
        integer :: max_depth = 8
        !> The sparse solver (cfrd --linear-solver; cfrd_linear_solver): not a deck card, as
        !> the results are the same to round-off [choice]
        integer :: linear_solver = linear_solver_auto
        type(effects_t) :: effects            !! the EFFECTS card (applied by the reader)
    end type model_t

contains

    !> The deck keyword of a material law.
    pure function law_name(law) result(name)
        integer, intent(in) :: law
        character(len=:), allocatable :: name
        select case (law)
        case (law_elastic)
            name = 'ELASTIC'
        case (law_duncan_eb)
            name = 'EB'
        case (law_goodman)
            name = 'GOODMAN'
        case (law_pjoint)
            name = 'PJOINT'
        case default
            name = 'UNKNOWN'
        end select
    end function law_name

    !> Whether a material law is one of a zero-thickness joint (GOODMAN, PJOINT).
    pure logical function is_joint_law(law)
        integer, intent(in) :: law
        is_joint_law = law == law_goodman .or. law == law_pjoint
    end function is_joint_law

    !> Whether an element kind is a zero-thickness joint.
    pure logical function is_joint_kind(kind)
        integer, intent(in) :: kind
        is_joint_kind = kind == elem_joint_gauss .or. kind == elem_joint_lobatto
    end function is_joint_kind

    !> The deck keyword of an interface method.
    pure function method_name(method) result(name)
        integer, intent(in) :: method
        character(len=:), allocatable :: name
        name = merge('JOINT', 'THIN ', method == method_joint)
        name = trim(name)
    end function method_name

    !> The deck keyword of a contact scheme.
    pure function scheme_name(scheme) result(name)
        integer, intent(in) :: scheme
        character(len=:), allocatable :: name
        name = trim(merge('MORTAR', 'NTS   ', scheme == scheme_mortar))
    end function scheme_name

    !> The deck keyword of a contact search.
    pure function search_name(search) result(name)
        integer, intent(in) :: search
        character(len=:), allocatable :: name
        name = trim(merge('LINEAR', 'RPIM  ', search == search_linear))
    end function search_name

    !> The deck keyword of a stage kind.
    pure function stage_kind_name(kind) result(name)
        integer, intent(in) :: kind
        character(len=:), allocatable :: name
        select case (kind)
        case (stage_fill)
            name = 'FILL'
        case (stage_load)
            name = 'LOAD'
        case (stage_reset)
            name = 'RESET'
        case (stage_water)
            name = 'WATER'
        case (stage_wait)
            name = 'WAIT'
        case (stage_wet)
            name = 'WET'
        case default
            name = 'UNKNOWN'
        end select
    end function stage_kind_name

    !> Whether some material of the model creeps (then the state keeps creep strains).
    pure logical function has_creep(model)
        type(model_t), intent(in) :: model
        has_creep = .false.
        if (allocated(model%materials)) has_creep = any(model%materials%creep)
    end function has_creep

    !> Whether some material of the model collapses on wetting (WETTING cards).
    pure logical function has_wetting(model)
        type(model_t), intent(in) :: model
        has_wetting = .false.
        if (allocated(model%materials)) has_wetting = any(model%materials%wetting)
    end function has_wetting

    !> The active elements after a FILL stage of `group`: those active before and the
    !> group's (the one activation rule: the stage driver, its preparation ahead, the check).
    pure function fill_active(mesh, active, group) result(after)
        type(mesh_t), intent(in) :: mesh
        logical, intent(in) :: active(:)
        integer, intent(in) :: group
        logical :: after(size(active))
        after = active .or. mesh%group == group
    end function fill_active
end module cfrd_model
