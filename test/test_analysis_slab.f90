!> The slab's section forces against beam theory (issue 22): a slab of Q4S quads on an
!> elastic (Winkler) foundation of Goodman joints, under a point load and an axial force,
!> against Hetenyi's closed form of the infinite beam on an elastic foundation (Hetenyi,
!> Beams on Elastic Foundation, 1946, ch. II; docs/theory.md section 13). Built in code,
!> independent of the deck reader.
module test_analysis_slab
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check, fail
    use cfrd_model, only: model_t, stage_t, stage_load, elem_quad4_shear
    use cfrd_results, only: results_t, slab_result_t, body_extremes_t, singular_radius_t
    use cfrd_interface, only: slab_stresses
    use cfrd_body_extremes, only: body_extremes
    use cfrd_beam_foundation, only: vesic_modulus, decay_rate, decay_radius
    use cfrd_stage_driver, only: run_analysis
    use cfrd_listing, only: resolution_note
    use cfrd_test_models, only: new_model, elastic_material
    use test_analysis_slab_clamp, only: test_clamped_slab, slab_on_winkler
    implicit none
    private

    public :: collect_analysis_slab

    real(dp), parameter :: deg = 0.017453292519943295769_dp

contains

    subroutine collect_analysis_slab(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [new_unittest('hetenyi_point_load', test_hetenyi), &
                 new_unittest('extremes_without_singular_points', test_extremes), &
                 new_unittest('vesic_worked_example', test_vesic), &
                 new_unittest('skewed_columns_are_sections', test_skewed_columns), &
                 new_unittest('clamped_slab_moment', test_clamped_slab), &
                 new_unittest('resolution_of_the_reported_section', test_resolution)]
    end subroutine collect_analysis_slab

    !> A slab 28 m long, h = 0.6 m thick in two layers of 56 Q4S quads each (0.5 m), on its
    !> 35 deg slope, E = 3.0e7 kPa, nu = 0 (plane strain = beam: EI = E h^3 / 12), resting on
    !> Gauss joints (kn = k = 1.0e5 kPa/m, the foundation modulus per m of slab; ks = 1e-3 k,
    !> all but frictionless) over fixed nodes. Loads: P = 1000 kN/m normal to the slab at
    !> mid-length (towards the foundation), and H = 3000 kN/m pressing on both ends along the
    !> axis. Closed form: beta = (k / (4 EI))^(1/4) = 0.4639 1/m, beta L/2 = 6.5, so the free
    !> ends change the infinite beam's figures by e^-6.5 = 0.15 % of their peaks; with
    !> x the distance from the load, M = -P/(4 beta) e^(-beta x) (cos beta x - sin beta x)
    !> (the section's M is + with tension on the side away from the foundation, so the
    !> sagging M of Hetenyi is negative here), V = sign P/2 e^(-beta x) cos beta x, N = -H,
    !> fibre stresses N/h +- 6 M/h^2. Tolerances, set from what beam theory leaves out:
    !> the slab's shear deformation, (E/(kappa G)) (h beta)^2 / 12 = 1.5 % of the deflection
    !> (Timoshenko), and the element (beta l = 0.23): M and the fibre stresses' bending part
    !> to 3 % of their peak, V to 3 % of P/2, N to 1 % of H. Measured: M 0.49 %, V 0.13 %,
    !> N 0.05 %, fibre stresses 0.52 % of their peaks. (The slab's elements must be longer
    !> than thick: slab_stresses takes an element's longer axis as the slab's.)
    !> (The slab on its joints: slab_on_winkler of test_analysis_slab_clamp.)
    !> The decay length (the summary's radius around a singular point, docs/theory.md
    !> section 13): Hetenyi's V vanishes first at lambda x = pi/2 on each side of the load,
    !> so twice the distance of the FE shear's first zero (linear between sections) is
    !> pi / lambda; against pi / decay_rate(k, EI, 1 m) to 3 % (the tolerance of V above: a
    !> 0.13 % error of V moves the zero by 0.4 %). Measured: see the line printed.
    subroutine test_hetenyi(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(results_t) :: results
        integer, parameter :: nx = 56
        real(dp), parameter :: length = 28.0_dp, h = 0.6_dp, e = 3.0e7_dp, k = 1.0e5_dp, &
                               p = 1000.0_dp, hf = 3000.0_dp
        real(dp) :: t(2), n(2), beta, x, m_ref, v_ref, m_peak, s_load, worst(4), zero(2), &
                    reach
        real(dp), allocatable :: xy(:, :)
        integer :: i, j, nsec
        t = [cos(35.0_dp*deg), sin(35.0_dp*deg)]
        n = [-t(2), t(1)]
        ! Nodes: the slab's three rows (row j at zeta = h j / 2), then the fixed base row.
        allocate (xy(2, 4*(nx + 1)))
        do j = 0, 2
            do i = 0, nx
                xy(:, node(i, j)) = length*i/nx*t + h*j/2.0_dp*n
            end do
        end do
        do i = 0, nx
            xy(:, node(i, 3)) = length*i/nx*t
        end do
        call slab_on_winkler(model, xy, nx, 2, e, 0.0_dp, k, elem_quad4_shear)
        associate (f => model%load_sets(1)%nodal_force)
            f(:, node(nx/2, 1)) = -p*n
            ! H on each end section, consistent nodal forces of a uniform traction.
            do j = 0, 2
                f(:, node(0, j)) = f(:, node(0, j)) + hf*weight(j)*t
                f(:, node(nx, j)) = f(:, node(nx, j)) - hf*weight(j)*t
            end do
        end associate
        model%stages(1) = stage_t(kind=stage_load, load_set=1, increments=1, label='HETENYI')
        call run_analysis(model, results, error)
        if (allocated(error)) return
        beta = (k/(4.0_dp*e*h**3/12.0_dp))**0.25_dp
        m_peak = p/(4.0_dp*beta)
        associate (r => results%stages(1)%slab)
            nsec = size(r%section_s)
            if (nsec /= nx) then
                call fail(error, 'expected one section per element column')
                return
            end if
            ! The load's node lies between sections nx/2 and nx/2 + 1.
            s_load = 0.5_dp*(r%section_s(nx/2) + r%section_s(nx/2 + 1))
            worst = 0.0_dp
            do i = 1, nsec
                x = r%section_s(i) - s_load
                m_ref = -m_peak*exp(-beta*abs(x))*(cos(beta*x) - sin(beta*abs(x)))
                v_ref = sign(0.5_dp*p, x)*exp(-beta*abs(x))*cos(beta*x)
                worst(1) = max(worst(1), abs(r%moment(i) - m_ref)/m_peak)
                worst(2) = max(worst(2), abs(r%shear(i) - v_ref)/(0.5_dp*p))
                worst(3) = max(worst(3), abs(r%axial(i) + hf)/hf)
                worst(4) = max(worst(4), abs(r%sigma_water(i) - (-hf/h + 6.0_dp*m_ref/h**2))/ &
                               (6.0_dp*m_peak/h**2), &
                               abs(r%sigma_cushion(i) - (-hf/h - 6.0_dp*m_ref/h**2))/ &
                               (6.0_dp*m_peak/h**2))
            end do
            write (*, '(a,4(es10.3,a))') '    Hetenyi: M ', 100*worst(1), ' %, V ', &
                100*worst(2), ' %, N ', 100*worst(3), ' %, fibre stresses ', 100*worst(4), &
                ' % of their peaks'
            call check(error, worst(1) <= 0.03_dp, 'M within 3 % of P/(4 beta) of Hetenyi''s')
            if (allocated(error)) return
            call check(error, worst(2) <= 0.03_dp, 'V within 3 % of P/2 of Hetenyi''s')
            if (allocated(error)) return
            call check(error, worst(3) <= 0.01_dp, 'N within 1 % of H')
            if (allocated(error)) return
            call check(error, worst(4) <= 0.03_dp, 'fibre stresses within 3 % of 6M/h^2')
            if (allocated(error)) return
            ! The shear's first zero on each side of the load (V > 0 above it, < 0 below).
            zero = -1.0_dp
            do i = nx/2 + 1, nsec - 1
                if (r%shear(i) > 0.0_dp .and. r%shear(i + 1) <= 0.0_dp) then
                    zero(1) = crossing(r%section_s(i), r%shear(i), r%section_s(i + 1), &
                                       r%shear(i + 1)) - s_load
                    exit
                end if
            end do
            do i = nx/2, 2, -1
                if (r%shear(i) < 0.0_dp .and. r%shear(i - 1) >= 0.0_dp) then
                    zero(2) = s_load - crossing(r%section_s(i), r%shear(i), &
                                                r%section_s(i - 1), r%shear(i - 1))
                    exit
                end if
            end do
            if (any(zero < 0.0_dp)) then
                call fail(error, 'the shear has no zero on one side of the load')
                return
            end if
            reach = 4.0_dp*atan(1.0_dp)/decay_rate(k, e*h**3/12.0_dp, 1.0_dp)
            write (*, '(a,f8.4,a,f8.4,a,f6.3,a)') '    decay length: pi/lambda ', reach, &
                ' m, twice the FE shear''s first zero ', sum(zero), ' m (', &
                100*abs(sum(zero) - reach)/reach, ' %)'
            call check(error, abs(sum(zero) - reach) <= 0.03_dp*reach, &
                       'pi/lambda within 3 % of twice the first zero of V')
        end associate
    contains
        !> The zero of the line through (s1, v1) and (s2, v2).
        pure real(dp) function crossing(s1, v1, s2, v2)
            real(dp), intent(in) :: s1, v1, s2, v2
            crossing = s1 + (s2 - s1)*v1/(v1 - v2)
        end function crossing
        pure integer function node(i, j)
            integer, intent(in) :: i, j
            node = j*(nx + 1) + i + 1
        end function node
        pure real(dp) function weight(j)
            integer, intent(in) :: j
            weight = merge(4.0_dp/6.0_dp, 1.0_dp/6.0_dp, j == 1)
        end function weight
    end subroutine test_hetenyi

    !> Extremes per body without the singular points (constructed case): a slab of three
    !> 1 x 0.5 m quads (SLAB group) on three rockfill quads of 1 x 1 m, bonded, node 1 (the
    !> slab's lower corner, shared with the rockfill) fixed. Radius: the slab (E = 3e7 kPa,
    !> nu = 0.2, h = 0.5 m) on the rockfill of the same E and nu as a Vesic foundation,
    !> closed form written out here: D = E h^3 / (12 (1 - nu^2)), k = 0.65 (E / D)^(1/12)
    !> E / (1 - nu^2) (b = 1 m), pi / lambda = pi (4 D / k)^(1/4) = 1.439 m, more than 2 h =
    !> 1 m: slab element 1 (centroid 0.56 m from node 1) and rockfill element 4 (0.71 m) are
    !> left out, the others (1.52 m and more) are not. Given sigma1 = 900, 500, 700 and sigma3 = -900, -100, -300 in
    !> the slab, sigma1 = 80, 20, 10 and sigma3 = -800, -50, -60 in the rockfill: slab
    !> extremes 700 (element 3) and -300 (element 3), rockfill 20 (element 5) and -60
    !> (element 6), one element left out of each; singular nodes: node 1 alone. Slab
    !> sections: uniform sigma_xx 900, 500, 700 kPa, N/h = sigma_xx (uniform stress): the
    !> largest membrane stress outside the radius is 700 kPa, element 3's section.
    subroutine test_extremes(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(slab_result_t) :: slab
        type(body_extremes_t), allocatable :: ex(:)
        integer, allocatable :: nodes(:)
        real(dp), allocatable :: radius(:)
        type(singular_radius_t), allocatable :: why(:)
        real(dp) :: xy(2, 12), principal(3, 6), stress(4, 4, 6), d, k
        integer :: conn(4, 6), i
        ! Rows of 4 nodes at y = -1, 0, 0.5: rockfill below, slab above.
        do i = 0, 3
            xy(:, i + 1) = [1.0_dp*i, 0.0_dp]
            xy(:, i + 5) = [1.0_dp*i, 0.5_dp]
            xy(:, i + 9) = [1.0_dp*i, -1.0_dp]
        end do
        do i = 1, 3
            conn(:, i) = [i, i + 1, i + 5, i + 4]
            conn(:, i + 3) = [i + 8, i + 9, i + 1, i]
        end do
        call new_model(model, xy, conn, [(1, i=1, 6)], [elastic_material(3.0e7_dp, 0.2_dp, &
                                                                          0.0_dp)])
        model%mesh%group(1:3) = 1
        model%mesh%group_name = [character(len=10) :: 'SLAB']
        model%slab_groups = [1]
        allocate (model%interfaces(0))
        model%fixed(:, 1) = .true.
        model%fixed(:, 9:12) = .true.
        principal = 0.0_dp
        principal(1, :) = [900.0_dp, 500.0_dp, 700.0_dp, 80.0_dp, 20.0_dp, 10.0_dp]
        principal(2, :) = [-900.0_dp, -100.0_dp, -300.0_dp, -800.0_dp, -50.0_dp, -60.0_dp]
        ! Uniform sigma_xx of 900, 500 and 700 kPa in the slab elements (along their axis):
        ! N/h = sigma_xx and M = 0 in each section (closed form of a uniform stress).
        stress = 0.0_dp
        stress(1, :, 1:3) = spread([900.0_dp, 500.0_dp, 700.0_dp], 1, 4)
        call all_active_extremes(model, stress, principal, slab, ex, nodes, radius, why)
        call check(error, size(nodes), 1, 'one singular node')
        if (allocated(error)) return
        call check(error, nodes(1), 1, 'the slab''s fixed corner')
        if (allocated(error)) return
        d = 3.0e7_dp*0.5_dp**3/(12.0_dp*(1.0_dp - 0.2_dp**2))
        k = 0.65_dp*(3.0e7_dp/d)**(1.0_dp/12.0_dp)*3.0e7_dp/(1.0_dp - 0.2_dp**2)
        call check(error, radius(1), 4.0_dp*atan(1.0_dp)*(4.0_dp*d/k)**0.25_dp, &
                   'pi / lambda of the slab on a Vesic foundation', rel=1e-12_dp)
        if (allocated(error)) return
        call check(error, why(1)%support, 4, 'the supporting element')
        if (allocated(error)) return
        call check(error, all([ex%max_element, ex%min_element, ex%left_out] == &
                              [3, 5, 3, 6, 1, 1]), 'elements of the extremes, and left out')
        if (allocated(error)) return
        call check(error, all([ex%max_sigma1, ex%min_sigma3] == &
                              [700.0_dp, 20.0_dp, -300.0_dp, -60.0_dp]), 'extreme values')
        if (allocated(error)) return
        ! Sections: the first (centre 0.56 m from node 1) is left out; the largest membrane
        ! and fibre stress of the others is element 3's uniform 700 kPa, centre x = 2.5 m.
        call check(error, ex(1)%max_membrane, 700.0_dp, 'slab membrane stress N/h', &
                   rel=1e-9_dp)
        if (allocated(error)) return
        call check(error, ex(1)%max_fibre, 700.0_dp, 'slab fibre stress', rel=1e-9_dp)
        if (allocated(error)) return
        call check(error, slab%section_x(ex(1)%max_membrane_section), 2.5_dp, &
                   'section of the largest N/h', rel=1e-9_dp)
    end subroutine test_extremes

    !> Vesic's modulus against a published worked example (the calculation sheet "Calculation
    !> of the modulus of reaction of the soil", scribd document 680935098, its line "(Vesic,
    !> 1961)"): a footing B = 3 m wide, h = 0.5 m thick (I = B h^3 / 12), Ec = 30620 MPa, on
    !> soil of E = 10 MPa, nu = 0.30: k = 2348.118 kN/m^3 (printed to 7 digits: 1e-6). And
    !> the radius of cfrd_beam_foundation: 2 h governs a slab on a stiff foundation (decay
    !> length below it), pi / lambda a soft one; a layer in series lowers k as 1/k + c.
    subroutine test_vesic(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: k, r, k1, r1, pi
        pi = 4.0_dp*atan(1.0_dp)
        call check(error, vesic_modulus(1.0e4_dp, 0.3_dp, 30620.0e3_dp*3.0_dp*0.5_dp**3/12.0_dp, &
                                        3.0_dp), 2348.118_dp, 'Vesic k of the worked example', &
                   rel=1e-6_dp)
        if (allocated(error)) return
        ! Hetenyi's lambda = (k b / (4 EI))^(1/4): k = 4 EI / b gives 1.
        call check(error, decay_rate(4.0e3_dp, 2.0e3_dp, 2.0_dp), 1.0_dp, 'lambda', &
                   rel=1e-14_dp)
        if (allocated(error)) return
        ! A slab of h = 0.9 m (E 3e7 kPa, nu 0.2) on E_s = 1e5 kPa, nu_s 0.3, alone and with a
        ! joint of kn = 1e5 kPa/m in series: pi / lambda from the closed forms.
        call decay_radius(0.9_dp, 3.0e7_dp, 0.2_dp, 1.0e5_dp, 0.3_dp, 0.0_dp, r, k)
        call check(error, k, 0.65_dp*(1.0e5_dp*12.0_dp*(1.0_dp - 0.2_dp**2)/ &
                                      (3.0e7_dp*0.9_dp**3))**(1.0_dp/12.0_dp)*1.0e5_dp/ &
                   (1.0_dp - 0.3_dp**2), 'k of the slab strip', rel=1e-12_dp)
        if (allocated(error)) return
        call check(error, r, pi*(4.0_dp*3.0e7_dp*0.9_dp**3/(12.0_dp*(1.0_dp - 0.2_dp**2))/k) &
                   **0.25_dp, 'pi / lambda', rel=1e-12_dp)
        if (allocated(error)) return
        call decay_radius(0.9_dp, 3.0e7_dp, 0.2_dp, 1.0e5_dp, 0.3_dp, 1.0e-5_dp, r1, k1)
        call check(error, k1, 1.0_dp/(1.0_dp/k + 1.0e-5_dp), 'k with a joint in series', &
                   rel=1e-12_dp)
        if (allocated(error)) return
        call check(error, r1, r*(k/k1)**0.25_dp, 'pi / lambda with the joint', rel=1e-12_dp)
        if (allocated(error)) return
        call decay_radius(0.9_dp, 3.0e7_dp, 0.2_dp, 0.0_dp, 0.3_dp, 0.0_dp, r, k)
        call check(error, r == 0.0_dp .and. k == 0.0_dp, 'no foundation: no decay length')
    end subroutine test_vesic

    !> Sections of a slab cut along skewed lines (constructed case): 3 columns of 8 layers,
    !> each element 2 m along the axis and h/8 across, every cross line skewed so that a
    !> column's layers shift by 1.9 m along the axis from its first to its last (the x8
    !> Tianshengqiao-I slab on the row lines: 1.2 m in 1.6 m elements). Under a uniform
    !> sigma_tt = a, each column is one section, N = a h (the column's elements found by
    !> their cross lines, not by how close their centroids lie), and with FT = f_t the
    !> crack-risk ratio is the fibre stress a over f_t; 1e-12 relative.
    subroutine test_skewed_columns(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(slab_result_t) :: res
        integer, parameter :: nl = 8
        real(dp), parameter :: a = -2500.0_dp, h = 0.6_dp, len = 2.0_dp, shift = 1.9_dp, &
                               ft = 2000.0_dp
        real(dp) :: xy(2, 4*(nl + 1)), stress(4, 4, 3*nl)
        integer :: conn(4, 3*nl), i, j, e
        do j = 0, nl
            do i = 0, 3
                xy(:, 4*j + i + 1) = [len*i + shift*j/nl, h*j/nl]
            end do
        end do
        e = 0
        do j = 0, nl - 1
            do i = 0, 2
                e = e + 1
                conn(:, e) = [4*j + i + 1, 4*j + i + 2, 4*(j + 1) + i + 2, 4*(j + 1) + i + 1]
            end do
        end do
        call new_model(model, xy, conn, [(1, i=1, 3*nl)], [elastic_material(3.0e7_dp, &
                                                                              0.2_dp, 0.0_dp)])
        model%materials(1)%tensile_strength = ft
        model%mesh%group = 1
        model%mesh%group_name = [character(len=10) :: 'SLAB']
        model%slab_groups = [1]
        allocate (model%interfaces(0))
        stress = 0.0_dp
        stress(1, :, :) = a
        call slab_stresses(model, stress, [(.true., i=1, 3*nl)], res)
        call check(error, size(res%axial), 3, 'one section per column')
        if (allocated(error)) return
        do j = 1, 3
            call check(error, res%axial(j), a*h, 'N = a h', rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, res%crack_ratio(j), a/ft, 'crack-risk ratio a / f_t', rel=1e-12_dp)
            if (allocated(error)) return
        end do
    end subroutine test_skewed_columns

    !> The summary's check of the slab's resolution (docs/theory.md section 13): the element
    !> length a along the slope at the section of the largest fibre stress against
    !> pi / (6 lambda) of the radius. Constructed case: a slab of n quads a m long and
    !> h = 0.25 m thick (E = 3e7 kPa, nu = 0.2) on a row of rockfill quads 1 m deep (E_s =
    !> 1e4 kPa, nu_s = 0.3), bonded, the slab's lower corner (node 1) and the rockfill's
    !> base fixed. Closed form of theory.md section 13, by hand: D = E h^3 / (12 (1 - nu^2))
    !> = 40690.10 kN m, k = 0.65 (E_s / D)^(1/12) E_s / (1 - nu_s^2) = 6354.50 kPa/m (b = 1
    !> m), pi / lambda = pi (4 D / k)^(1/4) = 7.0675 m (> 2 h), pi / (6 lambda) = 1.17792 m.
    !> Uniform sigma_xx falling along the slab, 1000 - 10 i kPa in element i: the largest
    !> fibre stress and N/h outside the radius are those of the first section beyond 7.07 m.
    !> a = 1.0 m (n = 12): that section is a 1.0 m element, 1.0 <= 1.178: resolved.
    !> a = 1.5 m (n = 8): 1.5 > 1.178: not resolved.
    subroutine test_resolution(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: d, k, limit
        d = 3.0e7_dp*0.25_dp**3/(12.0_dp*(1.0_dp - 0.2_dp**2))
        k = 0.65_dp*(1.0e4_dp/d)**(1.0_dp/12.0_dp)*1.0e4_dp/(1.0_dp - 0.3_dp**2)
        limit = 4.0_dp*atan(1.0_dp)*(4.0_dp*d/k)**0.25_dp/6.0_dp
        call check(error, limit, 1.17792_dp, 'pi / (6 lambda), by hand', rel=1e-5_dp)
        if (allocated(error)) return
        call one_slab(12, 1.0_dp, 8, '  slab     resolution: resolved: a =  1.000 m (max'// &
                      ' fibre),  1.000 m (max N/h) <= pi/(6 lambda) =  1.178 m')
        if (allocated(error)) return
        call one_slab(8, 1.5_dp, 6, '  slab     resolution: not resolved: a =  1.500 m >'// &
                      ' pi/(6 lambda) =  1.178 m at the max fibre section')
    contains
        !> n slab elements of length a; the largest fibre stress expected at section j, the
        !> listing's note expected to begin with `expected`.
        subroutine one_slab(n, a, j, expected)
            integer, intent(in) :: n, j
            real(dp), intent(in) :: a
            character(len=*), intent(in) :: expected
            character(len=:), allocatable :: note
            type(model_t) :: model
            type(slab_result_t) :: slab
            type(body_extremes_t), allocatable :: ex(:)
            real(dp) :: xy(2, 3*(n + 1)), principal(3, 2*n), stress(4, 4, 2*n)
            integer :: conn(4, 2*n), i, m
            m = n + 1
            ! Rows of n + 1 nodes at y = 0 (shared), 0.25 (slab top), -1 (rockfill base).
            do i = 0, n
                xy(:, i + 1) = [a*i, 0.0_dp]
                xy(:, i + 1 + m) = [a*i, 0.25_dp]
                xy(:, i + 1 + 2*m) = [a*i, -1.0_dp]
            end do
            do i = 1, n
                conn(:, i) = [i, i + 1, i + 1 + m, i + m]
                conn(:, i + n) = [i + 2*m, i + 1 + 2*m, i + 1, i]
            end do
            call new_model(model, xy, conn, [(1, i=1, n), (2, i=1, n)], &
                           [elastic_material(3.0e7_dp, 0.2_dp, 0.0_dp), &
                            elastic_material(1.0e4_dp, 0.3_dp, 0.0_dp)])
            model%mesh%group(1:n) = 1
            model%mesh%group_name = [character(len=10) :: 'SLAB']
            model%slab_groups = [1]
            allocate (model%interfaces(0))
            model%fixed(:, 1) = .true.
            model%fixed(:, 2*m + 1:3*m) = .true.
            principal = 0.0_dp
            stress = 0.0_dp
            do i = 1, n
                stress(1, :, i) = 1000.0_dp - 10.0_dp*i
            end do
            call all_active_extremes(model, stress, principal, slab, ex)
            call check(error, ex(1)%max_section == j .and. ex(1)%max_membrane_section == j, &
                       'the largest fibre stress and N/h at the first section beyond the radius')
            if (allocated(error)) return
            call check(error, ex(1)%fibre_length, a, 'element length at the max fibre', &
                       rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, ex(1)%membrane_length, a, 'element length at the max N/h', &
                       rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, ex(1)%resolution_limit, limit, 'pi / (6 lambda)', rel=1e-12_dp)
            if (allocated(error)) return
            note = resolution_note(ex(1))
            call check(error, index(note, expected) == 1, 'the note: '//note)
        end subroutine one_slab
    end subroutine test_resolution

    !> The slab's sections and the extremes per body of a model whose elements are all
    !> active solids.
    subroutine all_active_extremes(model, stress, principal, slab, ex, nodes, radius, why)
        type(model_t), intent(in) :: model
        real(dp), intent(in) :: stress(:, :, :), principal(:, :)
        type(slab_result_t), intent(out) :: slab
        type(body_extremes_t), allocatable, intent(out) :: ex(:)
        integer, allocatable, intent(out), optional :: nodes(:)
        real(dp), allocatable, intent(out), optional :: radius(:)
        type(singular_radius_t), allocatable, intent(out), optional :: why(:)
        integer, allocatable :: n(:)
        real(dp), allocatable :: r(:)
        type(singular_radius_t), allocatable :: w(:)
        logical :: on(model%mesh%nelem)
        on = .true.
        call slab_stresses(model, stress, on, slab)
        call body_extremes(model, principal, on, on, slab, ex, n, r, w)
        if (present(nodes)) nodes = n
        if (present(radius)) radius = r
        if (present(why)) why = w
    end subroutine all_active_extremes
end module test_analysis_slab
