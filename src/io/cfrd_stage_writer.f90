!> Each stage's results written behind the analysis (docs/performance.md (ag)): while
!> stage k+1 is solved, a second thread writes stage k to the result files (add_stage: the
!> HDF5 group with its deflate, the CSV rows, the legacy listing). write_stage_behind hands
!> over a copy of the stage and returns (the last stage, with nothing left to overlap, is
!> written before it returns); it first waits for the stage handed over before it, so one
!> write at most runs behind, and the stages reach the files in their order and
!> as add_stage writes them on the caller's thread: the same bytes. Each stage is reported
!> (cfrd's progress line) after its write, so a stage reported is in the files, as before
!> (a run killed after "stage 3/" keeps stage 3: tools/cli_failure_test.sh).
!> wait_stage_writes waits for the last and returns the first write's error; every use of
!> the run's output other than these two (finish_output, keep_incomplete, discard_output,
!> its summaries) comes after it. The thread (cfrd_behind.c) takes one job at a time;
!> HDF5 is built thread-safe (Debian's libhdf5.settings: "Threadsafety: yes"), so the
!> analysis may read a restart file meanwhile. One run's writes at a time per process
!> (module state).
module cfrd_stage_writer
    use, intrinsic :: iso_c_binding, only: c_funptr, c_funloc, c_long
    use hdf5, only: hid_t, h5eset_auto_f
    use cfrd_error, only: error_t
    use cfrd_model, only: model_t
    use cfrd_results, only: stage_result_t
    use cfrd_run_output, only: run_output_t, add_stage
    implicit none
    private

    public :: write_stage_behind, wait_stage_writes, stage_writes_behind, stage_report_i

    abstract interface
        !> What the run reports of stage `number` of `total` once it is written (cfrd's
        !> progress line): called on the writer's thread, after add_stage, in stage order.
        subroutine stage_report_i(number, total, stage)
            import :: stage_result_t
            integer, intent(in) :: number, total
            type(stage_result_t), intent(in) :: stage
        end subroutine stage_report_i
    end interface

    !> The write handed over: the run's output and model (the caller's, which stay in
    !> place until wait_stage_writes), the stage's copy and number, the file it is copied
    !> from (cfrd --restart), and the first error of the writes.
    type(run_output_t), pointer :: output => null()
    type(model_t), pointer :: model => null()
    type(stage_result_t), save :: stage_copy
    integer, save :: number = 0, total = 0
    procedure(stage_report_i), pointer, save :: report => null()
    integer(hid_t), allocatable, save :: source   ! absent (not allocated): written, not copied
    type(error_t), allocatable, save :: write_error

    interface
        subroutine c_behind_post(job) bind(C, name='cfrd_behind_post')
            import :: c_funptr
            type(c_funptr), value :: job
        end subroutine c_behind_post
        subroutine c_behind_wait() bind(C, name='cfrd_behind_wait')
        end subroutine c_behind_wait
        integer(c_long) function c_behind_jobs() bind(C, name='cfrd_behind_jobs')
            import :: c_long
        end function c_behind_jobs
    end interface

contains

    !> Hand stage `stage_number` of `stages` of `out` over to be written behind (add_stage's
    !> arguments; `copy_from`: its group is copied from that open results file), then
    !> reported by `reported_by` (whether or not the write succeeded). Nothing is written
    !> after a write has failed (wait_stage_writes returns that error); the stage is
    !> still reported.
    subroutine write_stage_behind(out, run_model, stage_number, stages, stage, reported_by, &
                                  copy_from)
        type(run_output_t), target, intent(inout) :: out
        type(model_t), target, intent(in) :: run_model
        integer, intent(in) :: stage_number, stages
        type(stage_result_t), intent(in) :: stage
        procedure(stage_report_i) :: reported_by
        integer(hid_t), intent(in), optional :: copy_from
        call c_behind_wait()
        if (stage_number == stages) then
            ! The last stage: no analysis is left to overlap, so it is written here, without
            ! the copy (a one-stage deck's run as before the thread).
            call write_and_report(out, run_model, stage_number, stages, stage, reported_by, &
                                  copy_from)
            return
        end if
        output => out
        model => run_model
        number = stage_number
        total = stages
        report => reported_by
        if (allocated(source)) deallocate (source)
        if (present(copy_from)) source = copy_from
        stage_copy = stage
        call c_behind_post(c_funloc(write_handed_over))
    end subroutine write_stage_behind

    !> Wait for the writes handed over; `error`, if not allocated already, takes the first
    !> of their errors (which is then forgotten here, for the next run).
    subroutine wait_stage_writes(error)
        type(error_t), allocatable, intent(inout) :: error
        call c_behind_wait()
        if (allocated(write_error)) then
            if (.not. allocated(error)) then
                call move_alloc(write_error, error)
            else
                deallocate (write_error)
            end if
        end if
        output => null()
        model => null()
    end subroutine wait_stage_writes

    !> The stage writes that ran on the second thread so far (0 where the caller ran them:
    !> the thread could not be started, or CFRD_WRITE_BEHIND=0).
    integer function stage_writes_behind() result(count)
        count = int(c_behind_jobs())
    end function stage_writes_behind

    !> The job: write_and_report with what was handed over.
    subroutine write_handed_over() bind(C)
        call write_and_report(output, model, number, total, stage_copy, report, source)
    end subroutine write_handed_over

    !> add_stage, unless an earlier write failed (its error is kept in write_error), then
    !> the stage's report. HDF5's automatic printing of its error stack is a setting of each
    !> thread; off here as on the run's thread (open_results_h5).
    subroutine write_and_report(out, run_model, stage_number, stages, stage, reported_by, &
                                copy_from)
        type(run_output_t), intent(inout) :: out
        type(model_t), intent(in) :: run_model
        integer, intent(in) :: stage_number, stages
        type(stage_result_t), intent(in) :: stage
        procedure(stage_report_i) :: reported_by
        integer(hid_t), intent(in), optional :: copy_from
        type(error_t), allocatable :: error
        integer :: hdferr
        call h5eset_auto_f(0, hdferr)
        if (.not. allocated(write_error)) then
            call add_stage(out, run_model, stage_number, stage, error, copy_from)
            if (allocated(error)) call move_alloc(error, write_error)
        end if
        call reported_by(stage_number, stages, stage)
    end subroutine write_and_report
end module cfrd_stage_writer
