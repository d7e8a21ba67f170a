!> The extreme stresses of a stage per body, the face slab (SLAB groups), the rockfill (the
!> other solids) and the plinth (PLINTH groups, when given), without the singular points (docs/theory.md section 13): a slab node
!> on a fixed support (the toe on the rock) is the corner of a stiff body held against a
!> soft one, where the elastic stresses grow without bound as the mesh is refined. The
!> elements whose centroid lies within a radius of such a node are left out: the larger of
!> two slab thicknesses (Saint-Venant) and pi / lambda, the reach of an end disturbance of
!> the slab as a beam on its cushion as an elastic foundation (cfrd_beam_foundation).
!> Pure reading of the stage's state: nothing here feeds back into the analysis.
module cfrd_body_extremes
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, law_elastic, law_duncan_eb, law_goodman, method_joint, &
                          method_thin
    use cfrd_results, only: slab_result_t, body_extremes_t, singular_radius_t
    use cfrd_beam_foundation, only: decay_radius
    use cfrd_duncan_eb, only: eb_initial_moduli
    use cfrd_material_law, only: eb_parameters
    implicit none
    private

    public :: body_extremes

    !> The least radius left out around a singular node, in slab thicknesses there
    !> [choice]: by Saint-Venant's principle the stresses of a beam return to beam theory
    !> about one to two depths from a local disturbance (Timoshenko and Goodier, Theory of
    !> Elasticity, 1951, section 18).
    real(dp), parameter :: radius_in_thicknesses = 2.0_dp

    !> The longest slab element along the slope that resolves the slab's bending, as a
    !> fraction of the decay length pi / lambda [choice, argued from the closed form]:
    !> a <= pi / (6 lambda), lambda a <= pi/6 = 0.52, where Q4S rectangles give Hetenyi's
    !> moment of a slab clamped on a Winkler foundation within about 2 % (2.2 % measured
    !> at lambda a = 0.5 by analysis_slab/clamped_slab_moment; 16 % at 1, 31 % at 2).
    real(dp), parameter :: resolution_fraction = 1.0_dp/6.0_dp

contains

    !> Extremes of the slab and the rockfill from the centroid principal stresses
    !> (3, nelem) and the slab's sections; `solid(e)`: element e has stresses (no joint, no
    !> thin layer); the singular nodes and their radii.
    !> `why(k)`: how radius(k) was found.
    subroutine body_extremes(model, principal, active, solid, slab, extremes, nodes, radius, &
                             why)
        type(model_t), intent(in) :: model
        real(dp), intent(in) :: principal(:, :)
        logical, intent(in) :: active(:), solid(:)
        type(slab_result_t), intent(in) :: slab
        type(body_extremes_t), allocatable, intent(out) :: extremes(:)
        integer, allocatable, intent(out) :: nodes(:)
        real(dp), allocatable, intent(out) :: radius(:)
        type(singular_radius_t), allocatable, intent(out) :: why(:)
        logical, allocatable :: in_slab(:), in_plinth(:), near(:), on_slab(:)
        real(dp), allocatable :: centres(:, :)
        real(dp) :: c(2)
        integer :: e, k, b, j
        associate (mesh => model%mesh)
            allocate (in_slab(mesh%nelem), in_plinth(mesh%nelem), near(mesh%nelem), &
                      on_slab(mesh%nnode), centres(2, mesh%nelem))
            ! each element's centroid (the mean of its nodes), once for the searches below
            do e = 1, mesh%nelem
                centres(:, e) = sum(mesh%x(:, mesh%conn(:, e)), dim=2)/size(mesh%conn, 1)
            end do
            in_plinth = .false.
            do e = 1, mesh%nelem
                in_slab(e) = solid(e) .and. any(model%slab_groups == mesh%group(e))
                if (allocated(model%plinth_groups)) in_plinth(e) = solid(e) .and. &
                    any(model%plinth_groups == mesh%group(e))
            end do
            ! Singular nodes: nodes of active slab elements held by a support.
            on_slab = .false.
            do e = 1, mesh%nelem
                if (in_slab(e) .and. active(e)) on_slab(mesh%conn(:, e)) = .true.
            end do
            nodes = pack([(k, k=1, mesh%nnode)], on_slab .and. any(model%fixed, dim=1))
            allocate (radius(size(nodes)), why(size(nodes)))
            do k = 1, size(nodes)
                why(k)%thickness = thickness_at(slab, mesh%x(:, nodes(k)))
                call end_disturbance(model, principal, active, solid, in_slab, in_plinth, &
                                     centres, nodes(k), why(k))
                radius(k) = max(radius_in_thicknesses*why(k)%thickness, why(k)%decay)
            end do
            near = .false.
            do e = 1, mesh%nelem
                do k = 1, size(nodes)
                    if (norm2(centres(:, e) - mesh%x(:, nodes(k))) < radius(k)) near(e) = .true.
                end do
            end do
            allocate (extremes(merge(3, 2, any(in_plinth))))
            extremes(1)%body = 'slab'
            extremes(2)%body = 'rockfill'
            if (size(extremes) == 3) extremes(3)%body = 'plinth'
            do b = 1, size(extremes)
                associate (ex => extremes(b))
                    do e = 1, mesh%nelem
                        if (.not. (active(e) .and. solid(e))) cycle
                        if (in_slab(e) .neqv. (b == 1)) cycle
                        if (in_plinth(e) .neqv. (b == 3)) cycle
                        if (near(e)) then
                            ex%left_out = ex%left_out + 1
                            cycle
                        end if
                        if (ex%max_element == 0) then
                            ex%max_element = e
                            ex%min_element = e
                        end if
                        if (principal(1, e) > principal(1, ex%max_element)) ex%max_element = e
                        if (principal(2, e) < principal(2, ex%min_element)) ex%min_element = e
                    end do
                    if (ex%max_element > 0) then
                        ex%max_sigma1 = principal(1, ex%max_element)
                        ex%min_sigma3 = principal(2, ex%min_element)
                    end if
                end associate
            end do
            ! The slab's largest fibre stress and membrane stress N/h over the sections
            ! outside the radii.
            if (allocated(slab%section_s)) then
                do j = 1, size(slab%section_s)
                    if (.not. slab%section_active(j)) cycle
                    c = [slab%section_x(j), slab%section_y(j)]
                    if (any([(norm2(c - mesh%x(:, nodes(k))) < radius(k), &
                              k=1, size(nodes))])) cycle
                    associate (ex => extremes(1))
                        if (ex%max_section == 0) then
                            ex%max_section = j
                            ex%max_fibre = fibre(j)
                            ex%max_membrane_section = j
                            ex%max_membrane = membrane(j)
                        end if
                        if (fibre(j) > ex%max_fibre) then
                            ex%max_section = j
                            ex%max_fibre = fibre(j)
                        end if
                        if (membrane(j) > ex%max_membrane) then
                            ex%max_membrane_section = j
                            ex%max_membrane = membrane(j)
                        end if
                    end associate
                end do
            end if
            ! The element length at the reported sections, and pi / (6 lambda) of the
            ! largest radius (the one the listing names).
            associate (ex => extremes(1))
                if (ex%max_section > 0) then
                    ex%fibre_length = slab%length(ex%max_section)
                    ex%membrane_length = slab%length(ex%max_membrane_section)
                end if
                if (size(nodes) > 0) ex%resolution_limit = &
                    resolution_fraction*why(maxloc(radius, dim=1))%decay
            end associate
        end associate
    contains
        real(dp) function fibre(j)
            integer, intent(in) :: j
            fibre = max(slab%sigma_water(j), slab%sigma_cushion(j))
        end function fibre
        !> The section's membrane (mean) stress N/h, kPa: the mean of its two fibre stresses.
        real(dp) function membrane(j)
            integer, intent(in) :: j
            membrane = 0.5_dp*(slab%sigma_water(j) + slab%sigma_cushion(j))
        end function membrane
    end subroutine body_extremes

    !> The reach pi / lambda of an end disturbance at singular node `node` (docs/theory.md
    !> section 13), the slab (thickness `why%thickness`, the concrete of a slab element on
    !> the node) on the nearest active solid of the rockfill (its centroid nearest the node)
    !> as an elastic foundation [choice]: an E-B element's initial moduli Ei and nu at its
    !> confining stress sigma3 (the centroid's, compression +), an elastic one's E and nu;
    !> with the nearest active interface element in series (a Goodman joint 1 / kn in
    !> compression, a thin layer t / M, M its constrained modulus). Nothing found (or a slab
    !> not elastic): decay 0.
    subroutine end_disturbance(model, principal, active, solid, in_slab, in_plinth, centres, &
                               node, why)
        type(model_t), intent(in) :: model
        real(dp), intent(in) :: principal(:, :)
        logical, intent(in) :: active(:), solid(:), in_slab(:), in_plinth(:)
        real(dp), intent(in) :: centres(:, :)    !! (2, nelem) the elements' centroids
        integer, intent(in) :: node
        type(singular_radius_t), intent(inout) :: why
        real(dp) :: e_slab, nu_slab, es, nus, compliance, d, best
        integer :: e, concrete, joint
        associate (mesh => model%mesh)
            concrete = 0
            do e = 1, mesh%nelem
                if (in_slab(e) .and. active(e) .and. any(mesh%conn(:, e) == node)) then
                    concrete = e
                    exit
                end if
            end do
            if (concrete == 0) return
            associate (mat => model%materials(mesh%material(concrete)))
                if (mat%law /= law_elastic) return
                e_slab = mat%youngs_modulus
                nu_slab = mat%poisson_ratio
            end associate
            best = huge(1.0_dp)
            do e = 1, mesh%nelem
                if (.not. (active(e) .and. solid(e)) .or. in_slab(e) .or. in_plinth(e)) cycle
                d = norm2(centres(:, e) - mesh%x(:, node))
                if (d < best) then
                    best = d
                    why%support = e
                end if
            end do
            if (why%support == 0) return
            associate (mat => model%materials(mesh%material(why%support)))
                select case (mat%law)
                case (law_duncan_eb)
                    call eb_initial_moduli(eb_parameters(mat, model%pa), &
                                           -principal(1, why%support), es, nus)
                case (law_elastic)
                    es = mat%youngs_modulus
                    nus = mat%poisson_ratio
                case default
                    return
                end select
            end associate
            why%es = es
            compliance = 0.0_dp
            joint = 0
            best = huge(1.0_dp)
            if (allocated(model%interfaces)) then
                do e = 1, size(model%interfaces)
                    if (.not. active(model%interfaces(e)%element)) cycle
                    d = norm2(centres(:, model%interfaces(e)%element) - mesh%x(:, node))
                    if (d < best) then
                        best = d
                        joint = e
                    end if
                end do
            end if
            if (joint > 0) compliance = layer_compliance(model, model%interfaces(joint)%element, &
                                                         model%interfaces(joint)%method)
            call decay_radius(why%thickness, e_slab, nu_slab, es, nus, compliance, why%decay, &
                              why%modulus)
        end associate
    end subroutine end_disturbance

    !> The compliance (m/kPa) of interface element `el` across its line: a Goodman joint's
    !> 1 / kn in compression, a thin layer's t / M (t = its area over its longer mid-line,
    !> M = E (1 - nu) / ((1 + nu) (1 - 2 nu)), the constrained modulus of a layer
    !> compressed across its thickness); 0 for other laws.
    pure real(dp) function layer_compliance(model, el, method) result(c)
        type(model_t), intent(in) :: model
        integer, intent(in) :: el, method
        real(dp) :: x(2, 4), area, span, m
        c = 0.0_dp
        associate (mat => model%materials(model%mesh%material(el)))
            if (method == method_joint .and. mat%law == law_goodman) then
                if (mat%kn_compression > 0.0_dp) c = 1.0_dp/mat%kn_compression
            else if (method == method_thin .and. mat%law == law_elastic) then
                x = model%mesh%x(:, model%mesh%conn(1:4, el))
                area = 0.5_dp*abs((x(1, 3) - x(1, 1))*(x(2, 4) - x(2, 2)) - &
                                  (x(1, 4) - x(1, 2))*(x(2, 3) - x(2, 1)))
                span = max(norm2(x(:, 2) + x(:, 3) - x(:, 1) - x(:, 4)), &
                           norm2(x(:, 3) + x(:, 4) - x(:, 1) - x(:, 2)))/2.0_dp
                m = mat%youngs_modulus*(1.0_dp - mat%poisson_ratio)/ &
                    ((1.0_dp + mat%poisson_ratio)*(1.0_dp - 2.0_dp*mat%poisson_ratio))
                if (span > 0.0_dp .and. m > 0.0_dp) c = area/span/m
            end if
        end associate
    end function layer_compliance

    !> The slab's thickness at point p: that of the active section nearest to it (0 without
    !> sections).
    pure real(dp) function thickness_at(slab, p) result(h)
        type(slab_result_t), intent(in) :: slab
        real(dp), intent(in) :: p(2)
        real(dp) :: d, best
        integer :: j
        h = 0.0_dp
        best = huge(1.0_dp)
        if (.not. allocated(slab%section_s)) return
        do j = 1, size(slab%section_s)
            if (.not. slab%section_active(j)) cycle
            d = norm2([slab%section_x(j), slab%section_y(j)] - p)
            if (d < best) then
                best = d
                h = slab%thickness(j)
            end if
        end do
    end function thickness_at
end module cfrd_body_extremes
