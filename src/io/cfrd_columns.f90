!> Column texts shared by the listing and the CSV writers: a stage's date and reservoir
!> level in fixed columns (from its full results or from its summary), reals for CSV, and
!> the comment line that gives a CSV its run id.
module cfrd_columns
    use cfrd_kinds, only: dp
    use cfrd_model, only: dry_level
    use cfrd_results, only: stage_result_t
    use cfrd_stage_summary, only: stage_summary_t
    implicit none
    private

    public :: csv_real, date_of, level_of, run_id_comment

    !> The stage's date in 10 columns ('-' when it has none).
    interface date_of
        module procedure date_of_result, date_of_summary
    end interface date_of

    !> The reservoir level in 10 columns ('empty' before the first WATER stage).
    interface level_of
        module procedure level_of_result, level_of_summary
    end interface level_of

contains

    !> The first line of every CSV of a result set: '# cfrd run_id ID' (docs/results.md;
    !> readers skip lines that start with '#').
    pure function run_id_comment(run_id) result(line)
        character(len=*), intent(in) :: run_id
        character(len=:), allocatable :: line
        line = '# cfrd run_id '//run_id
    end function run_id_comment

    !> A real for CSV: 10 significant digits, no blanks, no negative zero.
    function csv_real(x) result(text)
        real(dp), intent(in) :: x
        character(len=:), allocatable :: text
        character(len=24) :: buffer
        write (buffer, '(es17.9e3)') x + 0.0_dp
        text = trim(adjustl(buffer))
    end function csv_real

    function date_of_result(stage) result(text)
        type(stage_result_t), intent(in) :: stage
        character(len=10) :: text
        text = '-'
        if (allocated(stage%date)) text = date_text(stage%date)
    end function date_of_result

    function date_of_summary(stage) result(text)
        type(stage_summary_t), intent(in) :: stage
        character(len=10) :: text
        text = '-'
        if (allocated(stage%date)) text = date_text(stage%date)
    end function date_of_summary

    pure function date_text(date) result(text)
        character(len=*), intent(in) :: date
        character(len=10) :: text
        text = '-'
        if (len(date) > 0) text = date
    end function date_text

    function level_of_result(stage) result(text)
        type(stage_result_t), intent(in) :: stage
        character(len=10) :: text
        text = level_text(stage%water_level)
    end function level_of_result

    function level_of_summary(stage) result(text)
        type(stage_summary_t), intent(in) :: stage
        character(len=10) :: text
        text = level_text(stage%water_level)
    end function level_of_summary

    pure function level_text(level) result(text)
        real(dp), intent(in) :: level
        character(len=10) :: text
        if (level == dry_level) then
            text = '     empty'
        else
            write (text, '(f10.2)') level
        end if
    end function level_text
end module cfrd_columns
