!> The slab's bending moment beside a clamped toe against beam theory (issue 22,
!> docs/tianshengqiao.md section 11.3): a slab on an elastic (Winkler) foundation of Goodman
!> joints, clamped at one end, under a uniform load, meshed with the element lengths and
!> layers of the Tianshengqiao-I decks' slab at x2, x4 and x8 (7, 3.5, 1.75 m; 4, 8, 16
!> layers: the x1 decks' 2 [paper], halved with the rest of the mesh), as Q4 and
!> as Q4S, on rectangles and on the decks' parallelograms (cut along horizontal row lines,
!> the slope 1:1.4), against Hetenyi's semi-infinite beam clamped at its end (Hetenyi, Beams
!> on Elastic Foundation, 1946, ch. III). Built in code, independent of the deck reader.
module test_analysis_slab_clamp
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: check
    use cfrd_model, only: model_t, stage_t, stage_load, interface_element_t, elem_quad4, &
                          elem_quad4_shear, elem_joint_gauss, method_joint
    use cfrd_results, only: results_t
    use cfrd_stage_driver, only: run_analysis
    use cfrd_test_models, only: new_model, elastic_material, linear_joint
    implicit none
    private

    public :: test_clamped_slab, slab_on_winkler

    ! The slab of the Tianshengqiao-I decks at the toe (h, E, nu of its concrete) on the
    ! foundation modulus of its cushion (Vesic's k of the bonded x8 deck, section 11.2).
    real(dp), parameter :: h = 0.91_dp, e = 3.0e7_dp, nu = 0.2_dp, k = 6.3e4_dp, &
                           q = 1000.0_dp, length = 63.0_dp, skew = 1.4_dp, &
                           pi = 3.14159265358979323846_dp

contains

    !> Hetenyi, ch. III: a semi-infinite beam on a foundation k, clamped at x = 0 (w = w' = 0),
    !> under a uniform load q towards the foundation: w = q/k (1 - e^(-lx)(cos lx + sin lx)),
    !> M = q/(2 l^2) e^(-lx)(cos lx - sin lx) (+: tension on the side away from the foundation,
    !> the sections' sign), l = (k / (4 D))^(1/4), D = E h^3 / (12 (1 - nu^2)) (plane strain).
    !> l = 0.2993 1/m, M(0) = 5.58 MN m/m, first zero of M at pi/(4 l) = 2.62 m, trough
    !> -0.208 M(0) at pi/(2 l) = 5.25 m; the free far end (l L = 18.9) changes nothing.
    !> Tolerance, for the Q4S slab at the finest of the decks' lengths (a = 1.75 m), set from
    !> what the FE section leaves out before measuring: the element's constant curvature is
    !> M's mean over its length, M + a^2/24 M'', M'' <= 2 sqrt(2) l^2 M(0): 3.2 % of M(0);
    !> the slab's shear deformation, 1.8 % of the deflection (Timoshenko: (E/(kappa G))
    !> (h l)^2 / 12): 5 % of M(0) at every section beyond one slab thickness from the clamp
    !> (within it the clamp's corner is a continuum's, not a beam's). Every mesh's worst
    !> error and M at 5-20 m is printed: the lengths of x2 and x4 and the Q4 slab are reported
    !> (docs/tianshengqiao.md section 11.3), not asserted.
    subroutine test_clamped_slab(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: lengths(3) = [7.0_dp, 3.5_dp, 1.75_dp]
        integer, parameter :: layers(3) = [4, 8, 16]
        character(len=*), parameter :: names(4) = [character(len=16) :: 'Q4 rectangles', &
                                        'Q4 skewed', 'Q4S rectangles', 'Q4S skewed']
        real(dp) :: worst, m_at(4), shape(3)
        integer :: i, v
        write (*, '(a)') '    clamped slab on a Winkler foundation, M against Hetenyi''s:'
        write (*, '(a)') '    element  a (m)  worst |M - M_H| / M_H(0)   M at 5 / 10 / 15 / '// &
            '20 m (MN m/m)   first zero (m), trough (MN m/m) at (m)'
        write (*, '(a,25x,4f8.3,f10.2,f8.3,f6.2)') '    Hetenyi          ', &
            (reference(5.0_dp*i)/1e3_dp, i=1, 4), pi/(4*lambda()), &
            reference(pi/(2*lambda()))/1e3_dp, pi/(2*lambda())
        do v = 1, 4
            do i = 1, 3
                call clamped_slab(lengths(i), layers(i), v > 2, mod(v, 2) == 0, worst, m_at, &
                                  shape, error)
                if (allocated(error)) return
                write (*, '(4x,a16,f6.2,f14.1,a,8x,4f8.3,f10.2,f8.3,f6.2)') names(v), &
                    lengths(i), 100*worst, ' %', m_at/1e3_dp, shape(1), shape(2)/1e3_dp, shape(3)
                if (v == 3 .and. i == 3) then
                    call check(error, worst <= 0.05_dp, 'Q4S slab of 1.75 m elements: M '// &
                               'within 5 % of M(0) of Hetenyi''s clamped beam')
                    if (allocated(error)) return
                end if
            end do
        end do
    end subroutine test_clamped_slab

    !> Hetenyi's M (kN m/m) at x (m) from the clamp.
    pure real(dp) function reference(x)
        real(dp), intent(in) :: x
        real(dp) :: l
        l = lambda()
        reference = q/(2.0_dp*l**2)*exp(-l*x)*(cos(l*x) - sin(l*x))
    end function reference

    pure real(dp) function lambda()
        lambda = (k/(4.0_dp*e*h**3/(12.0_dp*(1.0_dp - nu**2))))**0.25_dp
    end function lambda

    !> The slab of elements a long in nl layers (Q4S when shear, else Q4), its cross lines
    !> normal to it or skewed (a layer's nodes shifted by skew times its height along it),
    !> the nodes of its first cross line fixed; returns the worst |M - M_H| / M_H(0) over
    !> the sections whose centre lies beyond h from the clamp, and M at 5, 10, 15, 20 m
    !> (linear between section centres; x of a section: its centre along the slab, less the
    !> clamp's mean position); shape: M's first zero (linear between sections, -1: none),
    !> its least value and where.
    subroutine clamped_slab(a, nl, shear, skewed, worst, m_at, shape, error)
        real(dp), intent(in) :: a
        integer, intent(in) :: nl
        logical, intent(in) :: shear, skewed
        real(dp), intent(out) :: worst, m_at(4), shape(3)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        real(dp), allocatable :: xy(:, :), x(:)
        integer :: nx, i, j
        real(dp) :: shift
        nx = nint(length/a)
        shift = merge(skew, 0.0_dp, skewed)
        allocate (xy(2, (nl + 2)*(nx + 1)))
        do j = 0, nl
            do i = 0, nx
                xy(:, slab_node(i, j, nx)) = [a*i + shift*h*j/nl, h*j/nl]
            end do
        end do
        do i = 0, nx
            xy(:, slab_node(i, nl + 1, nx)) = [a*i, 0.0_dp]
        end do
        call slab_on_winkler(model, xy, nx, nl, e, nu, k, &
                             merge(elem_quad4_shear, elem_quad4, shear))
        model%fixed(:, [(slab_node(0, j, nx), j=0, nl)]) = .true.
        ! q on the top face: consistent nodal forces a q (a q / 2 at the ends), -y.
        associate (f => model%load_sets(1)%nodal_force)
            do i = 0, nx
                f(2, slab_node(i, nl, nx)) = -q*a*merge(0.5_dp, 1.0_dp, i == 0 .or. i == nx)
            end do
        end associate
        model%stages(1) = stage_t(kind=stage_load, load_set=1, increments=1, label='CLAMP')
        call run_analysis(model, results, error)
        if (allocated(error)) return
        associate (r => results%stages(1)%slab)
            ! Distance along the slab (x) from the clamp's cross line at its middle node.
            x = r%section_x - xy(1, slab_node(0, nl/2, nx))
            worst = 0.0_dp
            do i = 1, size(x)
                if (x(i) > h) worst = max(worst, abs(r%moment(i) - reference(x(i))))
            end do
            worst = worst/reference(0.0_dp)
            do i = 1, 4
                m_at(i) = interpolate(x, r%moment, 5.0_dp*i)
            end do
            shape(1) = -1.0_dp
            do i = 1, size(x) - 1
                if (r%moment(i) > 0.0_dp .and. r%moment(i + 1) <= 0.0_dp) then
                    shape(1) = x(i) + (x(i + 1) - x(i))*r%moment(i)/(r%moment(i) - r%moment(i + 1))
                    exit
                end if
            end do
            i = minloc(r%moment, 1)
            shape(2:3) = [r%moment(i), x(i)]
        end associate
    end subroutine clamped_slab

    !> A slab of nx columns of nl layers of elements of the given kind (group SLAB, concrete
    !> e, nu) on a Winkler foundation of Gauss joints (kn = k, ks = 1e-3 k) over a fixed base
    !> row, for the slab tests. xy holds the nodes, row j = 0 .. nl of the slab (0 on the
    !> foundation) then the base row nl + 1, nx + 1 nodes a row, node (i, j) = j (nx + 1) +
    !> i + 1; elements: the slab's layers from the foundation up, then the joints.
    subroutine slab_on_winkler(model, xy, nx, nl, e, nu, k, kind)
        type(model_t), intent(out) :: model
        real(dp), intent(in) :: xy(:, :), e, nu, k
        integer, intent(in) :: nx, nl, kind
        integer :: conn(4, (nl + 1)*nx), mat((nl + 1)*nx), i, j, el, lower, upper
        el = 0
        do j = 0, nl
            do i = 0, nx - 1
                el = el + 1
                ! A layer's element, or (j = nl) the joint from the base row to the slab's.
                lower = merge(nl + 1, j, j == nl)
                upper = merge(0, j + 1, j == nl)
                conn(:, el) = [slab_node(i, lower, nx), slab_node(i + 1, lower, nx), &
                               slab_node(i + 1, upper, nx), slab_node(i, upper, nx)]
                mat(el) = merge(2, 1, j == nl)
            end do
        end do
        call new_model(model, xy, conn, mat, [elastic_material(e, nu, 0.0_dp), &
                                              linear_joint(k, 1.0e-3_dp*k)])
        model%mesh%kind(1:nl*nx) = kind
        model%mesh%kind(nl*nx + 1:) = elem_joint_gauss
        model%mesh%group(1:nl*nx) = 1
        model%mesh%group_name = [character(len=10) :: 'SLAB']
        model%slab_groups = [1]
        allocate (model%interfaces(nx))
        do i = 1, nx
            model%interfaces(i) = interface_element_t(element=nl*nx + i, line=1, &
                                                      method=method_joint)
        end do
        allocate (model%gauges(0), model%wet_faces(0))
        model%fixed(:, [(slab_node(i, nl + 1, nx), i=0, nx)]) = .true.
    end subroutine slab_on_winkler

    !> Node (i, j) of slab_on_winkler's mesh of nx columns: j (nx + 1) + i + 1.
    pure integer function slab_node(i, j, nx)
        integer, intent(in) :: i, j, nx
        slab_node = j*(nx + 1) + i + 1
    end function slab_node

    !> The value at s of the piecewise linear function through (x(i), v(i)), x ascending.
    pure real(dp) function interpolate(x, v, s)
        real(dp), intent(in) :: x(:), v(:), s
        integer :: i
        interpolate = v(size(v))
        do i = 1, size(x) - 1
            if (s <= x(i + 1)) then
                interpolate = v(i) + (v(i + 1) - v(i))*(s - x(i))/(x(i + 1) - x(i))
                return
            end if
        end do
    end function interpolate
end module test_analysis_slab_clamp
