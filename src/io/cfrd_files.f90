!> File operations the Fortran standard lacks: atomic rename and removal, folders, resolved
!> paths, bound to the C library in two layers (private bind(C) interfaces, public wrappers
!> returning error_t).
module cfrd_files
    use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_ptr, c_null_ptr, &
                                           c_associated, c_f_pointer
    use cfrd_error, only: error_t, fatal_error, io_error
    implicit none
    private

    public :: move_file, delete_file, base_name, strip_extension
    public :: path_exists, is_directory, make_directories, resolved_path

    integer(c_int), parameter :: f_ok = 0          !! access(2): the path exists
    integer(c_int), parameter :: mode_rwx = 511    !! mkdir(2): 0777, less the umask
    integer, parameter :: path_max = 4096          !! PATH_MAX on Linux

    interface
        integer(c_int) function c_rename(from, to) bind(C, name='rename')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: from(*), to(*)
        end function c_rename

        integer(c_int) function c_remove(path) bind(C, name='remove')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: path(*)
        end function c_remove

        integer(c_int) function c_access(path, mode) bind(C, name='access')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: mode
        end function c_access

        integer(c_int) function c_mkdir(path, mode) bind(C, name='mkdir')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: mode    ! mode_t: unsigned int on Linux
        end function c_mkdir

        !> With a null buffer realpath(3) returns a malloc'd string (freed with free(3)).
        type(c_ptr) function c_realpath(path, resolved) bind(C, name='realpath')
            import :: c_ptr, c_char
            character(kind=c_char), intent(in) :: path(*)
            type(c_ptr), value :: resolved
        end function c_realpath

        subroutine c_free(pointer) bind(C, name='free')
            import :: c_ptr
            type(c_ptr), value :: pointer
        end subroutine c_free
    end interface

contains

    !> Rename `from` to `to`, replacing `to` atomically (POSIX rename on one file system).
    subroutine move_file(from, to, error)
        character(len=*), intent(in) :: from, to
        type(error_t), allocatable, intent(out) :: error
        if (c_rename(from//c_null_char, to//c_null_char) /= 0) then
            call fatal_error(error, 'cannot rename '//from//' to '//to, io_error)
        end if
    end subroutine move_file

    !> Remove a file if it exists; silent otherwise (used to clean up temporary files).
    subroutine delete_file(path)
        character(len=*), intent(in) :: path
        integer(c_int) :: status
        status = c_remove(path//c_null_char)
    end subroutine delete_file

    !> Whether anything (file, folder, ...) exists at `path`.
    logical function path_exists(path)
        character(len=*), intent(in) :: path
        path_exists = c_access(path//c_null_char, f_ok) == 0
    end function path_exists

    !> Whether `path` is a folder (or a link to one): 'path/.' exists only then.
    logical function is_directory(path)
        character(len=*), intent(in) :: path
        is_directory = c_access(path//'/.'//c_null_char, f_ok) == 0
    end function is_directory

    !> Create the folder `path` and any missing parent (mkdir -p); nothing when it exists.
    subroutine make_directories(path, error)
        character(len=*), intent(in) :: path
        type(error_t), allocatable, intent(out) :: error
        integer :: k
        integer(c_int) :: status
        if (is_directory(path)) return
        ! Every parent, each prefix that ends before a '/' (not the root, not '//'), then
        ! the path itself; a failure shows as a folder still missing at the end.
        do k = 2, len(path)
            if (path(k:k) /= '/' .or. path(k - 1:k - 1) == '/') cycle
            if (.not. is_directory(path(:k - 1))) &
                status = c_mkdir(path(:k - 1)//c_null_char, mode_rwx)
        end do
        status = c_mkdir(path//c_null_char, mode_rwx)
        if (.not. is_directory(path)) &
            call fatal_error(error, 'cannot create the folder '//path, io_error)
    end subroutine make_directories

    !> The absolute path without '.', '..' or links (realpath(3)); `path` itself when it
    !> cannot be resolved (it does not exist).
    function resolved_path(path) result(resolved)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: resolved
        type(c_ptr) :: p
        character(kind=c_char), pointer :: chars(:)
        integer :: n
        p = c_realpath(path//c_null_char, c_null_ptr)
        if (.not. c_associated(p)) then
            resolved = path
            return
        end if
        call c_f_pointer(p, chars, [path_max])
        n = 0
        do while (n < path_max)
            if (chars(n + 1) == c_null_char) exit
            n = n + 1
        end do
        allocate (character(len=n) :: resolved)
        resolved = transfer(chars(1:n), resolved)
        call c_free(p)
    end function resolved_path

    !> The last component of a path: 'inputs/dam.dat' -> 'dam.dat'.
    pure function base_name(path) result(name)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: name
        name = path(index(path, '/', back=.true.) + 1:)
    end function base_name

    !> The path without its extension: 'inputs/dam.dat' -> 'inputs/dam'.
    pure function strip_extension(path) result(stem)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: stem
        integer :: dot, slash
        dot = index(path, '.', back=.true.)
        slash = index(path, '/', back=.true.)
        if (dot > slash + 1) then
            stem = path(:dot - 1)
        else
            stem = path
        end if
    end function strip_extension
end module cfrd_files
