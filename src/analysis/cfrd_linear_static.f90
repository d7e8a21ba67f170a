!> Linear static analysis: all loads of the deck's default load set in one step, every
!> element active. Kept as the entry point of the verification tests; it is the stage driver
!> on a model whose stages are whatever the model says (one LOAD stage when the deck has no
!> STAGES group).
module cfrd_linear_static
    use cfrd_error, only: error_t
    use cfrd_model, only: model_t
    use cfrd_results, only: results_t
    use cfrd_stage_driver, only: run_analysis
    implicit none
    private

    public :: solve_linear_static

contains

    subroutine solve_linear_static(model, results, error)
        type(model_t), intent(in) :: model
        type(results_t), intent(out) :: results
        type(error_t), allocatable, intent(out) :: error
        call run_analysis(model, results, error)
    end subroutine solve_linear_static
end module cfrd_linear_static
