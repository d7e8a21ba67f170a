!> Column texts shared by the listing and the CSV writers: a stage's date and reservoir
!> level in fixed columns, and reals for CSV.
module cfrd_columns
    use cfrd_kinds, only: dp
    use cfrd_model, only: dry_level
    use cfrd_results, only: stage_result_t
    implicit none
    private

    public :: csv_real, date_of, level_of

contains

    !> A real for CSV: 10 significant digits, no blanks, no negative zero.
    function csv_real(x) result(text)
        real(dp), intent(in) :: x
        character(len=:), allocatable :: text
        character(len=24) :: buffer
        write (buffer, '(es17.9e3)') x + 0.0_dp
        text = trim(adjustl(buffer))
    end function csv_real

    !> The stage's date in 10 columns ('-' when it has none).
    function date_of(stage) result(text)
        type(stage_result_t), intent(in) :: stage
        character(len=10) :: text
        text = '-'
        if (allocated(stage%date)) then
            if (len(stage%date) > 0) text = stage%date
        end if
    end function date_of

    !> The reservoir level in 10 columns ('empty' before the first WATER stage).
    function level_of(stage) result(text)
        type(stage_result_t), intent(in) :: stage
        character(len=10) :: text
        if (stage%water_level == dry_level) then
            text = '     empty'
        else
            write (text, '(f10.2)') stage%water_level
        end if
    end function level_of
end module cfrd_columns
