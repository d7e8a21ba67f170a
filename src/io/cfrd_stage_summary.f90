!> What the listing, the terminal summary and the gauge, opening and perimetric-joint CSV
!> files need of a stage once its full results have been streamed to the HDF5 file: its
!> scalars, the extreme displacements since placement with their nodes, the gauges'
!> displacements, the slab openings and the perimetric joints. A few hundred bytes a stage,
!> so a run keeps one per stage and the full stage_result_t of the last stage only
!> (docs/results.md, "Streaming").
module cfrd_stage_summary
    use cfrd_kinds, only: dp
    use cfrd_model, only: model_t
    use cfrd_results, only: results_t, stage_result_t, opening_t, solver_stats_t, &
                            slab_result_t, pjoint_result_t
    implicit none
    private

    public :: stage_summary_t, summarise, summarise_run

    !> One stage in a few numbers (displacements since each node's placement).
    type :: stage_summary_t
        character(len=:), allocatable :: name      !! the stage's label
        character(len=:), allocatable :: date      !! calendar date, may be ''
        integer :: kind = 0
        integer :: increments = 0, factorisations = 0, iterations = 0, cutbacks = 0
        integer :: unbalanced = 0   !! increments accepted above ERRTOL at the depth limit
        real(dp) :: max_residual = 0.0_dp          !! largest |residual| / |load|
        real(dp) :: wall_time = 0.0_dp             !! s
        real(dp) :: water_level = 0.0_dp           !! m (dry_level: empty)
        integer :: active_elements = 0
        integer :: near_failure = 0                !! elements with stress level >= 0.95
        integer :: settlement_node = 0             !! node of the largest settlement (-uy)
        integer :: ux_max_node = 0, ux_min_node = 0
        real(dp) :: settlement = 0.0_dp            !! m, -uy at settlement_node
        real(dp) :: ux_max = 0.0_dp, ux_min = 0.0_dp   !! m
        real(dp), allocatable :: gauge_u(:, :)     !! (2, ngauges) m, ux, uy at the gauges
        type(opening_t), allocatable :: openings(:)    !! per line and slab phase
        !> the slab's sections (N, V, M, fibre stresses, crack-risk ratio), no Gauss points
        type(slab_result_t) :: slab
        type(pjoint_result_t) :: pjoint                !! the perimetric joints
        type(solver_stats_t) :: stats
    end type stage_summary_t

contains

    !> The summary of one stage.
    function summarise(model, stage) result(summary)
        type(model_t), intent(in) :: model
        type(stage_result_t), intent(in) :: stage
        type(stage_summary_t) :: summary
        integer :: ngauges
        summary%name = stage%name
        summary%date = ''
        if (allocated(stage%date)) summary%date = stage%date
        summary%kind = stage%kind
        summary%increments = stage%increments
        summary%factorisations = stage%factorisations
        summary%iterations = stage%iterations
        summary%cutbacks = stage%cutbacks
        summary%unbalanced = stage%unbalanced
        summary%max_residual = stage%max_residual
        summary%wall_time = stage%wall_time
        summary%water_level = stage%water_level
        summary%active_elements = count(stage%active)
        summary%near_failure = stage%near_failure
        associate (u => stage%displacement_total)
            summary%settlement_node = minloc(u(2, :), dim=1)
            summary%ux_max_node = maxloc(u(1, :), dim=1)
            summary%ux_min_node = minloc(u(1, :), dim=1)
            summary%settlement = -u(2, summary%settlement_node)
            summary%ux_max = u(1, summary%ux_max_node)
            summary%ux_min = u(1, summary%ux_min_node)
            ngauges = 0
            if (allocated(model%gauges)) ngauges = size(model%gauges)
            allocate (summary%gauge_u(2, ngauges))
            if (ngauges > 0) summary%gauge_u = u(:, model%gauges%node)
        end associate
        if (allocated(stage%openings)) then
            summary%openings = stage%openings
        else
            allocate (summary%openings(0))
        end if
        summary%slab = stage%slab
        if (allocated(summary%slab%element)) deallocate (summary%slab%element, summary%slab%x, &
                                                         summary%slab%y, summary%slab%s, &
                                                         summary%slab%sigma_t, summary%slab%tau, &
                                                         summary%slab%active)
        summary%pjoint = stage%pjoint
        summary%stats = stage%stats
    end function summarise

    !> The summaries of every stage of a run held in memory.
    function summarise_run(model, results) result(summaries)
        type(model_t), intent(in) :: model
        type(results_t), intent(in) :: results
        type(stage_summary_t), allocatable :: summaries(:)
        integer :: s
        allocate (summaries(size(results%stages)))
        do s = 1, size(results%stages)
            summaries(s) = summarise(model, results%stages(s))
        end do
    end function summarise_run
end module cfrd_stage_summary
