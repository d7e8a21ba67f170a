!> What an analysis hands to the writers: plain arrays per stage, no behaviour.
!> Sign convention: tension positive; stress components (xx, yy, zz, xy) in kPa.
module cfrd_results
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: stage_result_t, results_t, solver_stats_t
    public :: interface_result_t, opening_t, slab_result_t, contact_result_t, body_extremes_t
    public :: singular_radius_t
    public :: pjoint_result_t, carry_t

    !> Figures of the linear solves, for the listing and the benchmark.
    type :: solver_stats_t
        integer :: neq = 0                 !! equations (free dofs)
        integer :: nnz = 0                 !! stored nonzeros of the matrix
        real(dp) :: t_pattern = 0.0_dp     !! s, sparse pattern
        real(dp) :: t_assembly = 0.0_dp    !! s, stiffness and load assembly
        real(dp) :: t_symbolic = 0.0_dp    !! s, symbolic factorisation (CHOLMOD, UMFPACK)
        real(dp) :: t_numeric = 0.0_dp     !! s, numeric factorisation (CHOLMOD, UMFPACK)
        !> s, low-rank updates of a factorisation (contact rows changed, umfpack_t%update_rows)
        real(dp) :: t_update = 0.0_dp
        real(dp) :: t_solve = 0.0_dp       !! s, triangular solves
        !> s, contact search and geometry (contact_geometry: bucket search, couplings, gaps)
        !> and the active-set updates after each solve
        real(dp) :: t_contact = 0.0_dp
        real(dp) :: rcond = 0.0_dp         !! the library's reciprocal condition estimate
        integer :: patterns = 0            !! sparse patterns built (FILL; contact: couplings)
        integer :: analyses = 0            !! symbolic factorisations (orderings)
        !> of these, made ahead on a second thread while the stage before was solved
        !> (cfrd_linear_system's expect_next)
        integer :: analyses_ahead = 0
        !> matrices solved through an earlier factorisation by a low-rank row update instead
        !> of a numeric factorisation of their own (contact active-set iterations)
        integer :: updates = 0
        !> updated solves that missed UMFPACK's accuracy, and row updates refused for a
        !> non-finite w or capacitance matrix, so that the matrix was factorised
        integer :: updates_declined = 0
        !> nonzeros of L + U (UMFPACK) or L (CHOLMOD) of the last numeric factorisation
        integer :: lu_nnz = 0
        !> numeric factorisations by CHOLMOD (the symmetric positive definite matrices; the
        !> rest by UMFPACK, cfrd_linear_solver)
        integer :: cholesky = 0
        !> matrices CHOLMOD found not positive definite (or too badly conditioned), then
        !> factorised by UMFPACK
        integer :: cholesky_declined = 0
        !> contact: solves of the active-set iteration (each solve of an increment counts,
        !> the last one finds the set unchanged)
        integer :: contact_iterations = 0
        !> contact: global searches (the bucket search and the couplings; every increment with
        !> large slip, only when faces are placed with small slip)
        integer :: searches = 0
        !> contact: factorisations whose slip rows were regularised (a body sliding everywhere)
        integer :: regularised = 0
        !> contact: the most slave nodes held in stick in one solve after chatter or a cycle
        integer :: held = 0
        !> contact: the largest excess of a held node over its stick conditions (tension, or
        !> |q| - mu p), over the largest contact pressure of its solve
        real(dp) :: held_excess = 0.0_dp
    end type solver_stats_t

    !> Along the interface elements (model%interfaces, same order), two stations each (the
    !> joint's integration points; a thin layer's Gauss-point pairs across its thickness),
    !> in the element's frame (n from the cushion to the slab, t along the bottom face).
    type :: interface_result_t
        real(dp), allocatable :: x(:, :), y(:, :)     !! (2, ninterface) m
        real(dp), allocatable :: s(:, :)              !! (2, ninterface) m along the line
        real(dp), allocatable :: sigma_n(:, :)        !! (2, ninterface) kPa, tension +
        real(dp), allocatable :: tau(:, :)            !! (2, ninterface) kPa
        real(dp), allocatable :: du_n(:, :)           !! (2, ninterface) m, opening +
        real(dp), allocatable :: du_s(:, :)           !! (2, ninterface) m, slip along t
        logical, allocatable :: active(:)             !! (ninterface)
    end type interface_result_t

    !> At the slave nodes of the contact pairs (docs/theory.md section 14), in the order of
    !> the CONTACT SURFACE cards: status (0 open, 1 stick, 2 slip), gap (m, + open), slip
    !> accumulated along t (the slave normal turned counter-clockwise), and the contact
    !> tractions sigma_n (kPa, tension + so <= 0) and tau (kPa, on the slave along t).
    type :: contact_result_t
        integer, allocatable :: node(:), pair(:), status(:)     !! (ncontact)
        integer, allocatable :: group(:)                        !! (ncontact) of its slave face
        logical, allocatable :: placed(:)                       !! (ncontact) its face active
        real(dp), allocatable :: x(:), y(:)                     !! (ncontact) m, as meshed
        real(dp), allocatable :: s(:)                           !! (ncontact) m along the surface
        real(dp), allocatable :: gap(:), slip(:)                !! (ncontact) m
        real(dp), allocatable :: sigma_n(:), tau(:)             !! (ncontact) kPa
    end type contact_result_t

    !> The opening of one slab phase (the interface elements of one group on one line):
    !> width = largest relative normal displacement, depth = down-slope length of the
    !> tensile (open) zone from the phase's top (docs/theory.md section 13).
    type :: opening_t
        integer :: line = 0
        integer :: group = 0                 !! index into mesh%group_name, 0 = none
        real(dp) :: width = 0.0_dp           !! m
        real(dp) :: depth = 0.0_dp           !! m
        real(dp) :: length = 0.0_dp          !! m, length of the phase's interface
        real(dp) :: top(2) = 0.0_dp          !! m, top end of the phase's interface
        real(dp) :: max_compression = 0.0_dp !! kPa, most compressive sigma_n (<= 0)
        real(dp) :: max_tension = 0.0_dp     !! kPa, largest tensile sigma_n (>= 0)
        !> m, contact: the largest gap anywhere in the phase (an opening below a closed top
        !> counts here, not in width and depth); interfaces: the width
        real(dp) :: max_gap = 0.0_dp
    end type opening_t

    !> Stresses of the slab elements (SLAB groups) along the slab axis: at the Gauss points
    !> (normal stress along the element's long axis t and shear), and section resultants
    !> per column of elements across the slab (per m of dam length).
    type :: slab_result_t
        integer, allocatable :: element(:)            !! (nslab)
        real(dp), allocatable :: x(:, :), y(:, :)     !! (4, nslab) Gauss points, m
        real(dp), allocatable :: s(:, :)              !! (4, nslab) m along the slab axis
        real(dp), allocatable :: sigma_t(:, :)        !! (4, nslab) kPa, along the axis
        real(dp), allocatable :: tau(:, :)            !! (4, nslab) kPa
        logical, allocatable :: active(:)             !! (nslab)
        real(dp), allocatable :: section_s(:)         !! (nsection) m, centre along the axis
        real(dp), allocatable :: section_x(:), section_y(:)   !! (nsection) m
        real(dp), allocatable :: thickness(:)         !! (nsection) m
        real(dp), allocatable :: length(:)            !! (nsection) m, mean element length along the axis
        real(dp), allocatable :: axial(:)             !! (nsection) N, kN/m, tension +
        real(dp), allocatable :: shear(:)             !! (nsection) V, kN/m
        real(dp), allocatable :: moment(:)            !! (nsection) M, kN m/m, tension on the water side +
        real(dp), allocatable :: sigma_water(:)       !! (nsection) N/h + 6M/h^2, kPa
        real(dp), allocatable :: sigma_cushion(:)     !! (nsection) N/h - 6M/h^2, kPa
        !> (nsection) f_t of the section's concrete (ELASTIC FT), kPa; 0: not given
        real(dp), allocatable :: tensile_strength(:)
        !> (nsection) crack-risk ratio max(sigma_water, sigma_cushion) / f_t (0 without f_t)
        real(dp), allocatable :: crack_ratio(:)
        logical, allocatable :: section_active(:)     !! (nsection) all its elements active
    end type slab_result_t

    !> Extreme centroid stresses of one body (the slab: SLAB groups; the rockfill: the other
    !> solids) without the elements near singular points (docs/theory.md section 13).
    type :: body_extremes_t
        character(len=8) :: body = ''
        integer :: max_element = 0, min_element = 0   !! 0: no element of the body active
        real(dp) :: max_sigma1 = 0.0_dp               !! kPa, tension +
        real(dp) :: min_sigma3 = 0.0_dp               !! kPa
        integer :: max_section = 0                    !! slab: section of the largest fibre stress
        real(dp) :: max_fibre = 0.0_dp                !! slab: kPa, the larger fibre stress there
        integer :: max_membrane_section = 0           !! slab: section of the largest N/h
        real(dp) :: max_membrane = 0.0_dp             !! slab: kPa, the membrane stress N/h there
        integer :: left_out = 0                       !! active elements left out
        !> slab: m, the element length along the axis at the max fibre and max N/h sections
        real(dp) :: fibre_length = 0.0_dp, membrane_length = 0.0_dp
        !> slab: m, pi / (6 lambda) of the largest radius (0: lambda not known), the longest
        !> element that resolves the slab's bending (docs/theory.md section 13)
        real(dp) :: resolution_limit = 0.0_dp
    end type body_extremes_t

    !> How the radius around one singular node was found (docs/theory.md
    !> section 13; for the listing).
    type :: singular_radius_t
        real(dp) :: thickness = 0.0_dp   !! m, the slab's h at the node
        real(dp) :: decay = 0.0_dp       !! m, pi / lambda (0: no foundation found)
        real(dp) :: modulus = 0.0_dp     !! kPa/m, the foundation's k (with the interface)
        real(dp) :: es = 0.0_dp          !! kPa, the supporting element's modulus
        integer :: support = 0           !! the supporting element (0: none)
    end type singular_radius_t

    !> The perimetric joints (INTERFACE lines of PJOINT material; docs/theory.md section
    !> 12), one entry per line: the relative displacements of the slab
    !> side over the plinth side averaged over the line's length, in the joint's frame:
    !> opening along n (the slab moving away from the plinth), settlement along t (the
    !> slab moving across the joint, normal to the face, when the line runs from the face
    !> inwards), and the shear along the joint, out of the section's plane (0 in plane
    !> strain); with the mean tractions. Since the joint's placement.
    type :: pjoint_result_t
        integer, allocatable :: line(:)                  !! (npjoint) interface line number
        logical, allocatable :: active(:)                !! (npjoint) every element placed
        real(dp), allocatable :: opening(:)              !! (npjoint) m, + open
        real(dp), allocatable :: settlement(:)           !! (npjoint) m, along t
        real(dp), allocatable :: shear(:)                !! (npjoint) m, out of plane
        real(dp), allocatable :: sigma_n(:), tau(:)      !! (npjoint) kPa, tension +
    end type pjoint_result_t
    !> What the next stage needs of a stage's end beyond the stage's own fields (its
    !> displacement, Gauss-point stresses, strains, history, creep and wetting strains,
    !> active elements, water level and date): stored with the stage so that a run can
    !> restart from it (docs/results.md, "Restart"). The contact arrays are those of the
    !> contact state (cfrd_contact's contact_t), allocated only for decks with CONTACT pairs.
    type :: carry_t
        real(dp), allocatable :: u_before_reset(:, :)  !! (2, nnode) m, sum of u at the RESETs
        real(dp), allocatable :: f_ext(:, :)           !! (2, nnode) kN/m, applied so far
        logical :: prescribed_done = .false.           !! BOUNDARY values applied
        logical, allocatable :: wetted(:)              !! (nelem) wetted so far (WETTING decks)
        !> the contact multipliers' scale of the linear system in use (docs/theory.md s. 14)
        real(dp) :: contact_scale = 1.0_dp
        integer :: searches = 0
        logical, allocatable :: placed(:), supported(:)           !! (nc)
        logical, allocatable :: seg_searched(:), mseg_searched(:) !! (segments)
        integer, allocatable :: status(:), slip_sign(:)           !! (nc)
        integer, allocatable :: birth(:)                          !! (nnode)
        integer, allocatable :: cpl_ptr(:), cpl_node(:)           !! couplings
        real(dp), allocatable :: p(:), q(:), g0(:), gap(:), slip(:), w(:), wref(:), g(:)
        real(dp), allocatable :: g_curve(:), cpl_a(:)
        real(dp), allocatable :: u(:, :), normal(:, :), tangent(:, :)
        !> friction per master segment (a slave much finer than its master): the groups
        integer :: ngroup = 0
        integer, allocatable :: tgroup(:), grp_ptr(:), grp_node(:)
        real(dp), allocatable :: beta(:)
    end type carry_t

    !> The state at the end of one stage.
    type :: stage_result_t
        character(len=:), allocatable :: name      !! the stage's label, e.g. 'FILL L03'
        integer :: kind = 0                        !! stage_fill, stage_load, stage_reset
        integer :: increments = 0
        integer :: factorisations = 0              !! numeric factorisations in the stage
        integer :: iterations = 0                  !! Newton iterations in the stage
        integer :: cutbacks = 0                    !! increments halved (no convergence, or above ERRTOL)
        !> increments accepted above ERRTOL at the depth limit of the error control, and the
        !> warning of the first (docs/theory.md section 9, "Error control")
        integer :: unbalanced = 0
        character(len=:), allocatable :: warning
        real(dp) :: max_residual = 0.0_dp          !! largest |residual| / |load| after an increment
        !> |residual| / |load| of the stage's last increment solved by Newton iterations: after
        !> its midpoint step, then after each iteration (the rate of convergence, for tests)
        real(dp), allocatable :: newton_residuals(:)
        real(dp) :: wall_time = 0.0_dp             !! s
        logical, allocatable :: active(:)          !! (nelem) element active at the stage's end
        real(dp), allocatable :: stress_level(:)   !! (nelem) largest Gauss-point stress level
        integer :: near_failure = 0                !! elements with stress level >= 0.95
        character(len=:), allocatable :: date      !! the stage's calendar date, may be ''
        real(dp) :: water_level = 0.0_dp           !! reservoir level at the end, m (dry_level: empty)
        !> the date reached, as a day number since 1970-01-01 (-huge: no dated stage yet)
        real(dp) :: day = -huge(1.0_dp)
        !> (2, ngauss, nelem) volumetric and shear creep strains reached (decks with CREEP)
        real(dp), allocatable :: creep_gauss(:, :, :)
        !> (2, ngauss, nelem) wetting strains reached, volumetric and shear (WETTING cards)
        real(dp), allocatable :: wetting_gauss(:, :, :)
        real(dp), allocatable :: displacement(:, :)   !! (2, nnode) m, since the last RESET
        !> (2, nnode) m, since each node's placement: the displacements set to zero by
        !> RESET stages are added back (what a gauge installed with the fill measures)
        real(dp), allocatable :: displacement_total(:, :)
        real(dp), allocatable :: reaction(:, :)       !! (2, nnode) kN/m, zero at free dofs
        !> (4, ngauss=4, nelem) kPa at the integration points; a joint: (sigma_n, tau) in
        !> components 1-2 at its 2 points, the rest zero
        real(dp), allocatable :: stress_gauss(:, :, :)
        !> (4, ngauss=4, nelem) total strain since placement; a joint: relative displacements
        !> (du_n, du_s) in m
        real(dp), allocatable :: strain_gauss(:, :, :)
        !> (nhistory=2, ngauss=4, nelem) the laws' Gauss-point history: past maxima of the
        !> E-B stress-state function SS and of the stress level (zero for other laws)
        real(dp), allocatable :: history_gauss(:, :, :)
        real(dp), allocatable :: stress_centroid(:, :) !! (4, nelem) kPa
        real(dp), allocatable :: principal(:, :)      !! (3, nelem): sigma1, sigma3 (kPa), angle (deg)
        type(interface_result_t) :: interface        !! along the interface elements
        type(opening_t), allocatable :: openings(:)   !! per line and slab phase
        type(slab_result_t) :: slab                   !! along the face slab
        type(contact_result_t) :: contact             !! at the contact pairs' slave nodes
        !> per body (slab, rockfill; decks with SLAB cards), without the elements whose
        !> centroid lies within singular_radius(k) of singular_nodes(k)
        type(body_extremes_t), allocatable :: extremes(:)
        integer, allocatable :: singular_nodes(:)
        real(dp), allocatable :: singular_radius(:)   !! m
        type(singular_radius_t), allocatable :: singular_why(:)   !! how each radius was found
        type(pjoint_result_t) :: pjoint               !! the perimetric joints (PJOINT lines)
        real(dp) :: applied_load(2) = 0.0_dp          !! sum of applied forces, kN/m
        real(dp) :: reaction_sum(2) = 0.0_dp          !! sum of reactions, kN/m
        type(solver_stats_t) :: stats
        type(carry_t) :: carry                        !! the rest of the state, for a restart
    end type stage_result_t

    !> All stages of a run.
    type :: results_t
        type(stage_result_t), allocatable :: stages(:)
        real(dp) :: wall_time = 0.0_dp   !! s, whole analysis
    end type results_t
end module cfrd_results
