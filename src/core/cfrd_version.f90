!> The program's version, printed by `--version` and stored in every result file.
module cfrd_version
    implicit none
    private

    public :: cfrd_version_string

    character(len=*), parameter :: cfrd_version_string = '0.1.0'
end module cfrd_version
