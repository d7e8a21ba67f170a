!> Interface post-processing (docs/theory.md section 13): tractions and relative
!> displacements along the interface elements, the opening width and depth of each slab
!> phase, and the slab's stresses along its axis with section resultants. Pure reading of
!> the stage's state: nothing here feeds back into the analysis.
module cfrd_interface
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t, method_joint, elem_joint_lobatto, law_pjoint
    use cfrd_results, only: interface_result_t, opening_t, slab_result_t
    use cfrd_shape, only: gauss_2x2
    use cfrd_quad4, only: quad4_bmatrix
    use cfrd_joint4, only: joint_frame
    use cfrd_model_check, only: layer_thickness
    implicit none
    private

    public :: interface_stations, phase_openings, slab_stresses
    public :: open_stress, open_gap

    !> A station is open (in the tensile zone) when its normal stress exceeds open_stress,
    !> or, for a joint (whose cut-off may zero the stress), its opening exceeds open_gap.
    real(dp), parameter :: open_stress = 0.01_dp   !! kPa
    real(dp), parameter :: open_gap = 1.0e-6_dp    !! m

contains

    !> Stations of every interface element from the integration-point stresses and total
    !> strains (4, ngauss, nelem); joints at their two points, thin layers at the two pairs
    !> of Gauss points across the layer (1-4 and 2-3), rotated into the frame (n, t), with
    !> the relative displacements du = thickness * (eps_nn, gamma_nt).
    subroutine interface_stations(model, stress, strain, active, res)
        type(model_t), intent(in) :: model
        real(dp), intent(in) :: stress(:, :, :), strain(:, :, :)
        logical, intent(in) :: active(:)
        type(interface_result_t), intent(out) :: res
        real(dp), parameter :: g = 0.57735026918962576451_dp
        real(dp) :: t(2), n(2), length, s0, xi, thick, sig(4), eps(4), p(2, 4)
        integer :: k, e, j, line, a, b
        integer :: nif
        nif = size(model%interfaces)
        allocate (res%x(2, nif), res%y(2, nif), res%s(2, nif), res%sigma_n(2, nif), &
                  res%tau(2, nif), res%du_n(2, nif), res%du_s(2, nif), source=0.0_dp)
        allocate (res%active(nif))
        line = -1
        s0 = 0.0_dp
        do k = 1, nif
            e = model%interfaces(k)%element
            res%active(k) = active(e)
            if (model%interfaces(k)%line /= line) then
                line = model%interfaces(k)%line
                s0 = 0.0_dp
            end if
            p = model%mesh%x(:, model%mesh%conn(:, e))
            call joint_frame(p, t, n, length)
            do j = 1, 2
                if (model%interfaces(k)%method == method_joint) then
                    xi = merge(-1.0_dp, 1.0_dp, j == 1)
                    if (model%mesh%kind(e) /= elem_joint_lobatto) xi = xi*g
                    res%sigma_n(j, k) = stress(1, j, e)
                    res%tau(j, k) = stress(2, j, e)
                    res%du_n(j, k) = strain(1, j, e)
                    res%du_s(j, k) = strain(2, j, e)
                else
                    xi = merge(-g, g, j == 1)
                    ! Gauss points 1 (bottom) and 4 (top) near node 1; 2 and 3 near node 2.
                    a = merge(1, 2, j == 1)
                    b = merge(4, 3, j == 1)
                    sig = 0.5_dp*(stress(:, a, e) + stress(:, b, e))
                    eps = 0.5_dp*(strain(:, a, e) + strain(:, b, e))
                    thick = layer_thickness(p)
                    res%sigma_n(j, k) = n(1)**2*sig(1) + n(2)**2*sig(2) + 2.0_dp*n(1)*n(2)*sig(4)
                    res%tau(j, k) = t(1)*n(1)*sig(1) + t(2)*n(2)*sig(2) + &
                                    (t(1)*n(2) + t(2)*n(1))*sig(4)
                    res%du_n(j, k) = thick*(n(1)**2*eps(1) + n(2)**2*eps(2) + &
                                            n(1)*n(2)*eps(4))
                    res%du_s(j, k) = thick*(2.0_dp*(t(1)*n(1)*eps(1) + t(2)*n(2)*eps(2)) + &
                                            (t(1)*n(2) + t(2)*n(1))*eps(4))
                end if
                res%x(j, k) = 0.5_dp*((1.0_dp - xi)*p(1, 1) + (1.0_dp + xi)*p(1, 2))
                res%y(j, k) = 0.5_dp*((1.0_dp - xi)*p(2, 1) + (1.0_dp + xi)*p(2, 2))
                res%s(j, k) = s0 + 0.5_dp*(1.0_dp + xi)*length
            end do
            s0 = s0 + length
        end do
    end subroutine interface_stations

    !> Whether station j of interface element k is open, and the value that changes sign at
    !> the end of the open zone (the opening of a joint, the normal stress of a thin layer).
    pure subroutine station_state(model, res, k, j, is_open, value)
        type(model_t), intent(in) :: model
        type(interface_result_t), intent(in) :: res
        integer, intent(in) :: k, j
        logical, intent(out) :: is_open
        real(dp), intent(out) :: value
        if (model%interfaces(k)%method == method_joint) then
            is_open = res%sigma_n(j, k) > open_stress .or. res%du_n(j, k) > open_gap
            value = res%du_n(j, k) - open_gap
        else
            is_open = res%sigma_n(j, k) > open_stress
            value = res%sigma_n(j, k) - open_stress
        end if
    end subroutine station_state

    !> Opening width and depth of every slab phase: the active interface elements of one
    !> group on one line (not of a perimetric joint). Depth: from the phase's upper end down along the line while the
    !> stations are open, to the zero of the sign-changing value between the last open and
    !> the first closed station (linear interpolation); the whole length if all are open.
    subroutine phase_openings(model, res, openings)
        type(model_t), intent(in) :: model
        type(interface_result_t), intent(in) :: res
        type(opening_t), allocatable, intent(out) :: openings(:)
        integer, allocatable :: first(:), last(:)
        integer :: k, n, kk, j, step, idx, e
        real(dp) :: s_top, d, d_prev, v, v_prev, y_first, y_last
        logical :: is_open, going, top_is_end
        allocate (openings(0), first(0), last(0))
        ! Runs of consecutive interface elements with the same line and group.
        k = 1
        do while (k <= size(model%interfaces))
            kk = k
            do while (kk < size(model%interfaces))
                if (model%interfaces(kk + 1)%line /= model%interfaces(k)%line .or. &
                    model%mesh%group(model%interfaces(kk + 1)%element) /= &
                    model%mesh%group(model%interfaces(k)%element)) exit
                kk = kk + 1
            end do
            ! (a perimetric joint, PJOINT, is no slab phase: cfrd_pjoint_results)
            if (all(res%active(k:kk)) .and. model%materials(model%mesh%material( &
                model%interfaces(k)%element))%law /= law_pjoint) then
                openings = [openings, opening_t(line=model%interfaces(k)%line, &
                                                group=model%mesh%group( &
                                                model%interfaces(k)%element))]
                first = [first, k]
                last = [last, kk]
            end if
            k = kk + 1
        end do
        do n = 1, size(openings)
            associate (op => openings(n), x => model%mesh%x, conn => model%mesh%conn)
                e = model%interfaces(first(n))%element
                y_first = x(2, conn(1, e))
                op%length = element_end_s(last(n)) - element_start_s(first(n))
                e = model%interfaces(last(n))%element
                y_last = x(2, conn(2, e))
                top_is_end = y_last > y_first
                if (top_is_end) then
                    op%top = x(:, conn(2, e))
                    s_top = element_end_s(last(n))
                else
                    op%top = x(:, conn(1, model%interfaces(first(n))%element))
                    s_top = element_start_s(first(n))
                end if
                op%width = max(0.0_dp, maxval(res%du_n(:, first(n):last(n))))
                op%max_gap = op%width
                op%max_compression = min(0.0_dp, minval(res%sigma_n(:, first(n):last(n))))
                op%max_tension = max(0.0_dp, maxval(res%sigma_n(:, first(n):last(n))))
                ! Walk the stations from the top end down.
                step = merge(-1, 1, top_is_end)
                going = .true.
                op%depth = 0.0_dp
                d_prev = 0.0_dp
                v_prev = 0.0_dp
                idx = 0
                do kk = merge(last(n), first(n), top_is_end), &
                        merge(first(n), last(n), top_is_end), step
                    do j = merge(2, 1, top_is_end), merge(1, 2, top_is_end), step
                        if (.not. going) exit
                        call station_state(model, res, kk, j, is_open, v)
                        d = abs(res%s(j, kk) - s_top)
                        idx = idx + 1
                        if (is_open) then
                            d_prev = d
                            v_prev = v
                            op%depth = d
                            cycle
                        end if
                        going = .false.
                        if (idx > 1) op%depth = d_prev + (d - d_prev)*v_prev/(v_prev - v)
                    end do
                end do
                if (going .and. idx > 0) op%depth = op%length
            end associate
        end do
    contains
        real(dp) function element_start_s(k) result(s)
            integer, intent(in) :: k
            real(dp) :: t(2), nn(2), length
            call joint_frame(model%mesh%x(:, model%mesh%conn(:, model%interfaces(k)%element)), &
                             t, nn, length)
            s = 0.5_dp*(res%s(1, k) + res%s(2, k)) - 0.5_dp*length
        end function element_start_s

        real(dp) function element_end_s(k) result(s)
            integer, intent(in) :: k
            real(dp) :: t(2), nn(2), length
            call joint_frame(model%mesh%x(:, model%mesh%conn(:, model%interfaces(k)%element)), &
                             t, nn, length)
            s = 0.5_dp*(res%s(1, k) + res%s(2, k)) + 0.5_dp*length
        end function element_end_s
    end subroutine phase_openings

    !> Slab stresses along its axis. Each slab element's axis t is its longer pair of
    !> opposite face mid-points (pointing up, or to +x when level), n = t turned +90 deg (the
    !> water side of an upstream face with x downstream). Sections: the elements whose
    !> centroids, carried to the slab's straight fit along each element's cross mid-line,
    !> land at the same place (within a quarter of an element length) form one column
    !> across the slab; its resultants per m of dam are
    !> N = int sigma_tt dA / L, V = int tau dA / L, M = int sigma_tt (zeta - zeta_c) dA / L
    !> with zeta = n . x and L the mean element length along the axis.
    subroutine slab_stresses(model, stress, active, res)
        type(model_t), intent(in) :: model
        real(dp), intent(in) :: stress(:, :, :)
        logical, intent(in) :: active(:)
        type(slab_result_t), intent(out) :: res
        real(dp), allocatable :: centre_s(:), key_s(:), elem_len(:), elem_t(:, :), dv(:, :), &
                                 zeta(:, :)
        integer, allocatable :: order(:), section_of(:)
        real(dp) :: p(2, 4), a(2), b(2), t(2), nn(2), axis(2), origin(2), points(2, 4), &
                    weights(4), bee(4, 8), sig(4), c(2), w(2), area, zc, tol, ft
        integer :: ns, i, e, ig, nsec, j, m
        ns = 0
        do e = 1, model%mesh%nelem
            if (in_slab(e)) ns = ns + 1
        end do
        allocate (res%element(ns))
        allocate (res%x(4, ns), res%y(4, ns), res%s(4, ns), res%sigma_t(4, ns), &
                  res%tau(4, ns), source=0.0_dp)
        allocate (res%active(ns), centre_s(ns), key_s(ns), elem_len(ns), elem_t(2, ns), &
                  dv(4, ns), zeta(4, ns))
        if (ns == 0) then
            allocate (res%section_s(0), res%section_x(0), res%section_y(0), res%thickness(0), &
                      res%length(0), res%axial(0), res%shear(0), res%moment(0), &
                      res%sigma_water(0), res%sigma_cushion(0), res%tensile_strength(0), &
                      res%crack_ratio(0), res%section_active(0))
            return
        end if
        ns = 0
        do e = 1, model%mesh%nelem
            if (.not. in_slab(e)) cycle
            ns = ns + 1
            res%element(ns) = e
        end do
        ! The slab's straight fit: from the first to the farthest centroid.
        axis = slab_axis(model, res%element, origin)
        call gauss_2x2(points, weights)
        do i = 1, ns
            e = res%element(i)
            res%active(i) = active(e)
            p = model%mesh%x(:, model%mesh%conn(:, e))
            a = 0.5_dp*(p(:, 2) + p(:, 3)) - 0.5_dp*(p(:, 4) + p(:, 1))
            b = 0.5_dp*(p(:, 3) + p(:, 4)) - 0.5_dp*(p(:, 1) + p(:, 2))
            t = merge(a, b, norm2(a) >= norm2(b))
            elem_len(i) = norm2(t)
            t = t/elem_len(i)
            if (t(2) < 0.0_dp .or. (t(2) == 0.0_dp .and. t(1) < 0.0_dp)) t = -t
            elem_t(:, i) = t
            nn = [-t(2), t(1)]
            c = sum(p, dim=2)/4.0_dp
            centre_s(i) = dot_product(c - origin, axis)
            ! The column's place: the centroid carried to the axis along the element's cross
            ! mid-line w (normal to the axis on rectangles; along the row lines when skewed),
            ! the same for every layer of a column however skewed.
            w = merge(b, a, norm2(a) >= norm2(b))
            key_s(i) = centre_s(i) - dot_product(c - origin, [-axis(2), axis(1)])* &
                       dot_product(w, axis)/dot_product(w, [-axis(2), axis(1)])
            do ig = 1, 4
                call quad4_bmatrix(p, points(1, ig), points(2, ig), .false., bee, dv(ig, i))
                dv(ig, i) = dv(ig, i)*weights(ig)
                c = matmul(p, 0.25_dp*(1.0_dp + [-1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp]*points(1, ig))* &
                           (1.0_dp + [-1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp]*points(2, ig)))
                res%x(ig, i) = c(1)
                res%y(ig, i) = c(2)
                res%s(ig, i) = dot_product(c - origin, axis)
                zeta(ig, i) = dot_product(c, nn)
                sig = stress(:, ig, e)
                res%sigma_t(ig, i) = t(1)**2*sig(1) + t(2)**2*sig(2) + 2.0_dp*t(1)*t(2)*sig(4)
                res%tau(ig, i) = t(1)*nn(1)*sig(1) + t(2)*nn(2)*sig(2) + &
                                 (t(1)*nn(2) + t(2)*nn(1))*sig(4)
            end do
        end do
        ! Columns across the slab.
        order = sort_index(key_s)
        allocate (section_of(ns))
        tol = 0.25_dp*minval(elem_len)
        nsec = 1
        section_of(order(1)) = 1
        do i = 2, ns
            if (key_s(order(i)) - key_s(order(i - 1)) > tol) nsec = nsec + 1
            section_of(order(i)) = nsec
        end do
        allocate (res%section_s(nsec), res%section_x(nsec), res%section_y(nsec), &
                  res%thickness(nsec), res%length(nsec), res%axial(nsec), res%shear(nsec), &
                  res%moment(nsec), res%sigma_water(nsec), res%sigma_cushion(nsec), &
                  res%tensile_strength(nsec), res%crack_ratio(nsec), source=0.0_dp)
        allocate (res%section_active(nsec), source=.true.)
        do j = 1, nsec
            area = 0.0_dp
            zc = 0.0_dp
            m = 0
            do i = 1, ns
                if (section_of(i) /= j) cycle
                m = m + 1
                res%section_active(j) = res%section_active(j) .and. res%active(i)
                area = area + sum(dv(:, i))
                zc = zc + sum(dv(:, i)*zeta(:, i))
                res%section_s(j) = res%section_s(j) + centre_s(i)
                res%section_x(j) = res%section_x(j) + sum(res%x(:, i))/4.0_dp
                res%section_y(j) = res%section_y(j) + sum(res%y(:, i))/4.0_dp
                res%length(j) = res%length(j) + elem_len(i)
                ! f_t of the column: the smallest given by its elements' materials.
                ft = model%materials(model%mesh%material(res%element(i)))%tensile_strength
                if (ft > 0.0_dp .and. (res%tensile_strength(j) == 0.0_dp .or. &
                                       ft < res%tensile_strength(j))) res%tensile_strength(j) = ft
            end do
            zc = zc/area
            res%section_s(j) = res%section_s(j)/m
            res%section_x(j) = res%section_x(j)/m
            res%section_y(j) = res%section_y(j)/m
            ! Mean element length along the axis L, and the thickness h = area / L.
            res%length(j) = res%length(j)/m
            res%thickness(j) = area/res%length(j)
            do i = 1, ns
                if (section_of(i) /= j) cycle
                res%axial(j) = res%axial(j) + sum(res%sigma_t(:, i)*dv(:, i))
                res%shear(j) = res%shear(j) + sum(res%tau(:, i)*dv(:, i))
                res%moment(j) = res%moment(j) + sum(res%sigma_t(:, i)*(zeta(:, i) - zc)*dv(:, i))
            end do
            res%axial(j) = res%axial(j)/res%length(j)
            res%shear(j) = res%shear(j)/res%length(j)
            res%moment(j) = res%moment(j)/res%length(j)
            if (.not. res%section_active(j)) then
                res%axial(j) = 0.0_dp
                res%shear(j) = 0.0_dp
                res%moment(j) = 0.0_dp
            end if
            res%sigma_water(j) = res%axial(j)/res%thickness(j) + &
                                 6.0_dp*res%moment(j)/res%thickness(j)**2
            res%sigma_cushion(j) = res%axial(j)/res%thickness(j) - &
                                   6.0_dp*res%moment(j)/res%thickness(j)**2
            ! sigma_1 at a face (no shear there): the larger fibre stress (theory.md s. 13).
            if (res%tensile_strength(j) > 0.0_dp) res%crack_ratio(j) = &
                max(res%sigma_water(j), res%sigma_cushion(j))/res%tensile_strength(j)
        end do
    contains
        !> A solid element of a SLAB group (not one of the interface elements).
        logical function in_slab(e)
            integer, intent(in) :: e
            in_slab = any(model%slab_groups == model%mesh%group(e))
            if (in_slab .and. allocated(model%interfaces)) &
                in_slab = .not. any(model%interfaces%element == e)
        end function in_slab
    end subroutine slab_stresses

    !> Unit direction of the slab's straight fit (from the lowest slab centroid to the one
    !> farthest from it, pointing up) and its origin, the lowest centroid.
    function slab_axis(model, elements, origin) result(axis)
        type(model_t), intent(in) :: model
        integer, intent(in) :: elements(:)
        real(dp), intent(out) :: origin(2)
        real(dp) :: axis(2), c(2, size(elements)), far(2)
        integer :: i
        do i = 1, size(elements)
            c(:, i) = sum(model%mesh%x(:, model%mesh%conn(:, elements(i))), dim=2)/4.0_dp
        end do
        origin = c(:, minloc(c(2, :), dim=1))
        far = c(:, maxloc(sum((c - spread(origin, 2, size(elements)))**2, dim=1), dim=1))
        axis = far - origin
        if (norm2(axis) == 0.0_dp) then
            axis = [1.0_dp, 0.0_dp]
        else
            axis = axis/norm2(axis)
        end if
    end function slab_axis

    !> Indices that sort `v` ascending (insertion sort: slabs have tens to thousands of
    !> elements).
    pure function sort_index(v) result(idx)
        real(dp), intent(in) :: v(:)
        integer :: idx(size(v)), i, j, key
        idx = [(i, i=1, size(v))]
        do i = 2, size(v)
            key = idx(i)
            j = i - 1
            do while (j >= 1)
                if (v(idx(j)) <= v(key)) exit
                idx(j + 1) = idx(j)
                j = j - 1
            end do
            idx(j + 1) = key
        end do
    end function sort_index
end module cfrd_interface
