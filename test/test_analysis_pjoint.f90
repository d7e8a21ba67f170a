!> The perimetric joint (issue 22): the PJOINT law against its closed form, and a slab
!> block on a plinth block joined by a PJOINT line (built in code, independent of the deck
!> reader) against the statics of a uniform stress state.
module test_analysis_pjoint
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_model, only: model_t, material_t, stage_t, stage_load, interface_element_t, &
                          law_pjoint, elem_joint_lobatto, elem_joint_gauss, method_joint, &
                          solver_newton
    use cfrd_results, only: results_t
    use cfrd_stage_driver, only: run_analysis
    use cfrd_test_models, only: new_model, elastic_material, edge_traction
    use cfrd_pjoint, only: pjoint_params_t, pjoint_stress, pjoint_tangent
    use cfrd_material_law, only: material_update, material_update_tangent, nhistory
    implicit none
    private

    public :: collect_analysis_pjoint

    !> The stiffnesses of the tests: closed, open (waterstops), shear (kPa/m).
    real(dp), parameter :: knc = 1.0e7_dp, knt = 1.0e3_dp, ks = 2.0e3_dp

contains

    subroutine collect_analysis_pjoint(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('pjoint_law_closed_form', test_law), &
                new_unittest('pjoint_update_across_closure', test_update), &
                new_unittest('plinth_block_compression', test_compression), &
                new_unittest('plinth_block_tension_and_shear', test_tension_shear) &
                ]
    end subroutine collect_analysis_pjoint

    pure function pjoint_material() result(mat)
        type(material_t) :: mat
        mat%law = law_pjoint
        mat%label = 'perimetric joint'
        mat%kn_compression = knc
        mat%kn_tension = knt
        mat%ks_joint = ks
    end function pjoint_material

    !> The law's closed form (docs/theory.md section 12): sigma_n = knc du_n closed,
    !> knt du_n open, tau = ks du_s; its tangent diag(knc or knt, ks).
    subroutine test_law(error)
        type(error_t), allocatable, intent(out) :: error
        type(pjoint_params_t) :: p
        real(dp) :: s(2), d(2, 2)
        p = pjoint_params_t(kn_compression=knc, kn_tension=knt, ks=ks)
        s = pjoint_stress(p, [-2.0e-3_dp, 5.0e-3_dp])
        call check(error, s(1), -2.0e-3_dp*knc, 'closed sigma_n', rel=1e-14_dp)
        if (allocated(error)) return
        call check(error, s(2), 5.0e-3_dp*ks, 'closed tau', rel=1e-14_dp)
        if (allocated(error)) return
        s = pjoint_stress(p, [3.0e-3_dp, -1.0e-3_dp])
        call check(error, s(1), 3.0e-3_dp*knt, 'open sigma_n', rel=1e-14_dp)
        if (allocated(error)) return
        call check(error, s(2), -1.0e-3_dp*ks, 'open tau', rel=1e-14_dp)
        if (allocated(error)) return
        call pjoint_tangent(p, [0.0_dp, 1.0_dp], d)
        call check(error, d(1, 1), knc, 'kn at du_n = 0 (closed)', rel=1e-14_dp)
        if (allocated(error)) return
        call check(error, d(2, 2), ks, 'ks', rel=1e-14_dp)
        if (allocated(error)) return
        call check(error, abs(d(1, 2)) + abs(d(2, 1)), 0.0_dp, 'no coupling', abs=0.0_dp)
    end subroutine test_law

    !> An increment from closed (du_n = -1 mm, under the law's stress) to open (+2 mm):
    !> the update is exact, so the new tractions are the closed form at the end, the mid
    !> ones at the half-way displacement, and Newton's tangent is the one at the end.
    subroutine test_update(error)
        type(error_t), allocatable, intent(out) :: error
        type(material_t) :: mat
        real(dp) :: strain(4), de(4), stress(4), new(4), mid(4), c(4, 4), history(nhistory)
        logical :: midpoint
        integer :: m
        mat = pjoint_material()
        history = 0.0_dp
        strain = [-1.0e-3_dp, 4.0e-3_dp, 0.0_dp, 0.0_dp]
        stress = [-1.0e-3_dp*knc, 4.0e-3_dp*ks, 0.0_dp, 0.0_dp]
        de = [3.0e-3_dp, -6.0e-3_dp, 0.0_dp, 0.0_dp]
        do m = 0, 1
            midpoint = m == 1
            call material_update(mat, 101.325_dp, stress, strain, history, de, midpoint, &
                                 new, mid)
            call check(error, new(1), 2.0e-3_dp*knt, 'sigma_n after opening', rel=1e-14_dp)
            if (allocated(error)) return
            call check(error, new(2), -2.0e-3_dp*ks, 'tau after', rel=1e-14_dp)
            if (allocated(error)) return
            call check(error, mid(1), 0.5e-3_dp*knt, 'sigma_n half-way', rel=1e-14_dp)
            if (allocated(error)) return
            call check(error, mid(2), 1.0e-3_dp*ks, 'tau half-way', rel=1e-14_dp)
            if (allocated(error)) return
        end do
        call material_update_tangent(mat, 101.325_dp, stress, strain, history, de, c)
        call check(error, c(1, 1), knt, 'tangent kn at the end (open)', rel=1e-14_dp)
        if (allocated(error)) return
        call check(error, c(2, 2), ks, 'tangent ks', rel=1e-14_dp)
    end subroutine test_update

    !> A plinth block (height hp, fixed at its base) under a slab block (height hs), both
    !> nx x 1 quads of width w (E, nu = 0), joined along y = hp by a PJOINT line of nx
    !> joints (element kind `kind`), the top face loaded by the traction `t`. With nu = 0
    !> and the side tractions of the uniform state (sigma_yy = t(2), tau_xy = t(1)) the
    !> stress is uniform (statics): every joint carries (sigma_n, tau) = (t(2), t(1)), its
    !> relative displacements are (t(2)/kn, t(1)/ks) with kn = knc or knt by the sign of
    !> t(2), and so are the line's opening and settlement. Solved by Newton's iterations to 1e-10.
    subroutine plinth_blocks(results, kind, t, error)
        type(results_t), intent(out) :: results
        integer, intent(in) :: kind
        real(dp), intent(in) :: t(2)
        type(error_t), allocatable, intent(out) :: error
        integer, parameter :: nx = 3
        real(dp), parameter :: w = 3.0_dp, hp = 1.0_dp, hs = 0.8_dp, e = 3.0e7_dp
        type(model_t) :: model
        real(dp) :: x(2, 4*(nx + 1))
        integer :: conn(4, 3*nx), mat(3*nx), i
        do i = 0, nx
            x(:, i + 1) = [w*i/nx, 0.0_dp]                   ! plinth base (rock)
            x(:, nx + 2 + i) = [w*i/nx, hp]                  ! plinth top
            x(:, 2*nx + 3 + i) = [w*i/nx, hp]                ! slab bottom
            x(:, 3*nx + 4 + i) = [w*i/nx, hp + hs]           ! slab top
        end do
        do i = 1, nx
            conn(:, i) = [i, i + 1, nx + 2 + i, nx + 1 + i]
            conn(:, nx + i) = [2*nx + 2 + i, 2*nx + 3 + i, 3*nx + 4 + i, 3*nx + 3 + i]
            conn(:, 2*nx + i) = [nx + 1 + i, nx + 2 + i, 2*nx + 3 + i, 2*nx + 2 + i]
        end do
        mat = [(1, i=1, 2*nx), (2, i=1, nx)]
        call new_model(model, x, conn, mat, [elastic_material(e, 0.0_dp, 0.0_dp), &
                                             pjoint_material()])
        model%mesh%kind(2*nx + 1:) = kind
        allocate (model%interfaces(nx))
        do i = 1, nx
            model%interfaces(i) = interface_element_t(element=2*nx + i, line=2, &
                                                      method=method_joint)
        end do
        allocate (model%slab_groups(0), model%gauges(0), model%wet_faces(0))
        model%fixed(:, 1:nx + 1) = .true.
        associate (f => model%load_sets(1)%nodal_force)
            call edge_traction(model, [(3*nx + 3 + i, i=1, nx + 1)], t, f)
            ! the sides of the uniform state: tau_xy on x = w (+) and x = 0 (-), along y
            call edge_traction(model, [nx + 1, 2*nx + 2], [0.0_dp, t(1)], f)
            call edge_traction(model, [3*nx + 3, 4*nx + 4], [0.0_dp, t(1)], f)
            call edge_traction(model, [1, nx + 2], [0.0_dp, -t(1)], f)
            call edge_traction(model, [2*nx + 3, 3*nx + 4], [0.0_dp, -t(1)], f)
        end associate
        ! Newton to 1e-10: the bilinear law's branch settles in the iterations
        model%solver = solver_newton
        model%tolerance = 1.0e-10_dp
        model%max_iterations = 30
        model%stages(1) = stage_t(kind=stage_load, load_set=1, increments=2, label='PLINTH')
        call run_analysis(model, results, error)
    end subroutine plinth_blocks

    !> Compression: the slab pressed on the plinth by 500 kPa; the joint closes by p/knc,
    !> and the slab's top settles by p (hp + hs)/E + p/knc (1-D statics, nu = 0).
    subroutine test_compression(error)
        type(error_t), allocatable, intent(out) :: error
        type(results_t) :: results
        real(dp), parameter :: p = 500.0_dp
        integer :: k
        integer, parameter :: kinds(2) = [elem_joint_lobatto, elem_joint_gauss]
        do k = 1, 2
            call plinth_blocks(results, kinds(k), [0.0_dp, -p], error)
            if (allocated(error)) return
            associate (r => results%stages(1))
                call check(error, r%pjoint%opening(1), -p/knc, 'opening (closure)', &
                           rel=1e-9_dp)
                if (allocated(error)) return
                call check(error, r%pjoint%sigma_n(1), -p, 'sigma_n', rel=1e-9_dp)
                if (allocated(error)) return
                call check(error, r%displacement(2, size(r%displacement, 2)), &
                           -p*(1.8_dp/3.0e7_dp + 1.0_dp/knc), 'slab top uy', rel=1e-9_dp)
                if (allocated(error)) return
            end associate
        end do
    end subroutine test_compression

    !> Tension and shear: the slab pulled off the plinth by 2 kPa and sheared by 3 kPa;
    !> the waterstops open by q/knt, the joint slips (settlement) by tau/ks.
    subroutine test_tension_shear(error)
        type(error_t), allocatable, intent(out) :: error
        type(results_t) :: results
        real(dp), parameter :: q = 2.0_dp, tau = 3.0_dp
        call plinth_blocks(results, elem_joint_lobatto, [tau, q], error)
        if (allocated(error)) return
        associate (r => results%stages(1)%pjoint)
            call check(error, real(r%line(1), dp), 2.0_dp, 'line', abs=0.0_dp)
            if (allocated(error)) return
            call check(error, r%opening(1), q/knt, 'opening', rel=1e-9_dp)
            if (allocated(error)) return
            call check(error, r%settlement(1), tau/ks, 'settlement', rel=1e-9_dp)
            if (allocated(error)) return
            call check(error, r%tau(1), tau, 'tau', rel=1e-9_dp)
            if (allocated(error)) return
            call check(error, r%shear(1), 0.0_dp, 'shear (plane strain)', abs=0.0_dp)
        end associate
    end subroutine test_tension_shear
end module test_analysis_pjoint
