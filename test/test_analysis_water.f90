!> The reservoir load (issue 5, section 4): resultants of the hydrostatic pressure on a
!> sloped face against the closed forms, the cover group that moves the water from a cushion
!> face to the slab, and a staged water history against a one-step linear solve.
module test_analysis_water
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_model, only: model_t, wet_face_t, stage_t, stage_load, stage_water, stage_fill, &
                          gravity_load_t, all_groups
    use cfrd_results, only: results_t
    use cfrd_assembly, only: element_box_t, make_elements
    use cfrd_water, only: water_forces
    use cfrd_linear_static, only: solve_linear_static
    use cfrd_test_models, only: new_model, elastic_material, add_pressure
    implicit none
    private

    public :: collect_analysis_water

    real(dp), parameter :: gamma_w = 9.81_dp, slope = 1.4_dp
    integer, parameter :: nrow = 5
    real(dp), parameter :: row_height = 4.0_dp, width = 40.0_dp

contains

    subroutine collect_analysis_water(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('hydrostatic_resultants_sloped_face', test_resultants), &
                new_unittest('cover_group_moves_the_water', test_cover), &
                new_unittest('staged_water_equals_one_step', test_staged_water) &
                ]
    end subroutine collect_analysis_water

    !> A column of nrow quads under an upstream face of slope 1V:1.4H from (0, 0), right side
    !> vertical at x = width; face 4 (node 4 -> node 1) of every element is wetted.
    subroutine wedge_model(model)
        type(model_t), intent(out) :: model
        real(dp) :: x(2, 2*(nrow + 1))
        integer :: conn(4, nrow), j
        do j = 0, nrow
            x(:, 2*j + 1) = [slope*row_height*j, row_height*j]
            x(:, 2*j + 2) = [width, row_height*j]
        end do
        do j = 1, nrow
            conn(:, j) = [2*j - 1, 2*j, 2*j + 2, 2*j + 1]
        end do
        call new_model(model, x, conn, [(1, j=1, nrow)], &
                       [elastic_material(5.0e4_dp, 0.3_dp, 21.0_dp)])
        model%gamma_w = gamma_w
        model%fixed(:, 1:2) = .true.
        allocate (model%wet_faces(nrow), model%gauges(0))
        do j = 1, nrow
            model%wet_faces(j) = wet_face_t(element=j, face=4, cover=0)
        end do
    end subroutine wedge_model

    !> Water to h = 13 m (the waterline cuts the face of element 4): horizontal resultant
    !> gamma_w h^2/2, vertical the weight of the water wedge gamma_w 1.4 h^2/2, moment about
    !> the toe from resultants at y = h/3 and x = 1.4 h/3 (closed forms; 1e-12 relative,
    !> rounding only: the consistent forces of a linear pressure are exact).
    subroutine test_resultants(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(element_box_t), allocatable :: library(:)
        real(dp), allocatable :: f(:, :)
        real(dp) :: h, fx, fy, moment
        real(dp), parameter :: levels(3) = [13.0_dp, 8.0_dp, 19.99_dp]
        integer :: k
        call wedge_model(model)
        call make_elements(model, library, error)
        if (allocated(error)) return
        allocate (f(2, model%mesh%nnode))
        do k = 1, 3
            h = levels(k)
            call water_forces(model, library, [(.true., k=1, nrow)], h, f)
            fx = sum(f(1, :))
            fy = sum(f(2, :))
            moment = sum(model%mesh%x(1, :)*f(2, :) - model%mesh%x(2, :)*f(1, :))
            call check(error, fx, gamma_w*h**2/2, 'horizontal resultant', rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, fy, -gamma_w*slope*h**2/2, 'vertical resultant', rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, moment, -(slope*h/3)*gamma_w*slope*h**2/2 - &
                       (h/3)*gamma_w*h**2/2, 'moment about the toe', rel=1e-12_dp)
            if (allocated(error)) return
        end do
        ! Below the face's lowest point nothing is wet.
        call water_forces(model, library, [(.true., k=1, nrow)], -1.0_dp, f)
        call check(error, maxval(abs(f)), 0.0_dp, 'no load below the toe', abs=0.0_dp)
    end subroutine test_resultants

    !> A body column (x 0..10) behind a slab column (x -1..0) sharing its nodes: the body's
    !> face is wetted until group SLAB is placed, the slab's outer face once it is. The
    !> resultant is gamma_w h^2/2 either way; it acts on the x = 0 nodes before and on the
    !> x = -1 nodes after (closed form; 1e-12 relative).
    subroutine test_cover(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: model
        type(element_box_t), allocatable :: library(:)
        real(dp), allocatable :: f(:, :)
        real(dp) :: x(2, 3*(nrow + 1))
        integer :: conn(4, 2*nrow), j
        logical :: active(2*nrow)
        real(dp), parameter :: h = 11.0_dp
        do j = 0, nrow
            x(:, 3*j + 1) = [-1.0_dp, row_height*j]
            x(:, 3*j + 2) = [0.0_dp, row_height*j]
            x(:, 3*j + 3) = [10.0_dp, row_height*j]
        end do
        do j = 1, nrow
            conn(:, j) = [3*j - 1, 3*j, 3*j + 3, 3*j + 2]            ! body
            conn(:, nrow + j) = [3*j - 2, 3*j - 1, 3*j + 2, 3*j + 1]  ! slab
        end do
        call new_model(model, x, conn, [(1, j=1, 2*nrow)], &
                       [elastic_material(5.0e4_dp, 0.3_dp, 21.0_dp)])
        model%mesh%group_name = [character(len=10) :: 'SLAB']
        model%mesh%group(nrow + 1:) = 1
        allocate (model%wet_faces(2*nrow))
        do j = 1, nrow
            model%wet_faces(j) = wet_face_t(element=j, face=4, cover=1)
            model%wet_faces(nrow + j) = wet_face_t(element=nrow + j, face=4, cover=0)
        end do
        call make_elements(model, library, error)
        if (allocated(error)) return
        allocate (f(2, model%mesh%nnode))
        active = [(.true., j=1, nrow), (.false., j=1, nrow)]
        call water_forces(model, library, active, h, f)
        call check(error, sum(f(1, 2::3)), gamma_w*h**2/2, 'before: on the body face', &
                   rel=1e-12_dp)
        if (allocated(error)) return
        call check(error, maxval(abs(f(:, 1::3))), 0.0_dp, 'before: slab nodes dry', &
                   abs=0.0_dp)
        if (allocated(error)) return
        active = .true.
        call water_forces(model, library, active, h, f)
        call check(error, sum(f(1, 1::3)), gamma_w*h**2/2, 'after: on the slab face', &
                   rel=1e-12_dp)
        if (allocated(error)) return
        call check(error, maxval(abs(f(:, 2::3))), 0.0_dp, 'after: body face covered', &
                   abs=0.0_dp)
    end subroutine test_cover

    !> Linear elastic wedge: gravity, then the reservoir up to 13 m in 3 steps, then down to
    !> 8 m. The path does not matter in linear elasticity, so the displacements must equal
    !> one linear solve under gravity and PRESSURE cards for 8 m of water on the faces of
    !> elements 1 and 2 (the existing, independently verified edge load); 1e-9 relative.
    !> The reactions must balance weight plus water (closed form) at every stage.
    subroutine test_staged_water(error)
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: staged, one_step
        type(results_t) :: r_staged, r_one
        real(dp) :: weight, h, expected(2)
        real(dp), parameter :: levels(3) = [0.0_dp, 13.0_dp, 8.0_dp]
        integer :: s
        call wedge_model(staged)
        staged%load_sets(1)%gravity = [gravity_load_t(all_groups, 0.0_dp, -1.0_dp)]
        deallocate (staged%stages)
        allocate (staged%stages(3))
        staged%stages(1) = stage_t(kind=stage_load, label='LOAD', date='')
        staged%stages(2) = stage_t(kind=stage_water, level=13.0_dp, increments=3, &
                                   label='WATER 13', date='1997-05')
        staged%stages(3) = stage_t(kind=stage_water, level=8.0_dp, increments=1, &
                                   label='WATER 8', date='1997-06')
        call solve_linear_static(staged, r_staged, error)
        if (allocated(error)) return
        ! Weight: the trapezoid between the face and x = width, 21 kN/m3 (closed form).
        weight = 21.0_dp*(width*nrow*row_height - slope*(nrow*row_height)**2/2)
        do s = 1, 3
            h = levels(s)
            expected = [-gamma_w*h**2/2, weight + gamma_w*slope*h**2/2]
            call check(error, r_staged%stages(s)%reaction_sum(1), expected(1), &
                       'x reaction, stage', rel=1e-9_dp, abs=1e-9_dp*weight)
            if (allocated(error)) return
            call check(error, r_staged%stages(s)%reaction_sum(2), expected(2), &
                       'y reaction, stage', rel=1e-9_dp)
            if (allocated(error)) return
        end do
        call check(error, r_staged%stages(3)%water_level, 8.0_dp, 'level recorded', &
                   abs=0.0_dp)
        if (allocated(error)) return

        call wedge_model(one_step)
        one_step%load_sets(1)%gravity = [gravity_load_t(all_groups, 0.0_dp, -1.0_dp)]
        ! Face 4 runs from node 4 (top) to node 1 (bottom).
        call add_pressure(one_step, 1, 4, gamma_w*(8.0_dp - 4.0_dp), gamma_w*8.0_dp)
        call add_pressure(one_step, 2, 4, 0.0_dp, gamma_w*(8.0_dp - 4.0_dp))
        call solve_linear_static(one_step, r_one, error)
        if (allocated(error)) return
        call check(error, maxval(abs(r_staged%stages(3)%displacement - &
                                     r_one%stages(1)%displacement)), 0.0_dp, &
                   'staged water = one-step pressure', &
                   abs=1e-9_dp*maxval(abs(r_one%stages(1)%displacement)))
    end subroutine test_staged_water
end module test_analysis_water
