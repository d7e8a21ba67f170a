!> File operations the Fortran standard lacks: atomic rename and removal, hard links,
!> folders and their files, resolved paths, bound to the C library in two layers (private
!> bind(C) interfaces, public wrappers returning error_t).
module cfrd_files
    use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_ptr, c_null_ptr, &
                                           c_associated, c_f_pointer, c_size_t, c_int64_t, &
                                           c_funptr, c_null_funptr
    use cfrd_error, only: error_t, fatal_error, io_error
    implicit none
    private

    public :: move_file, delete_file, base_name, strip_extension
    public :: path_exists, is_directory, make_directories, resolved_path
    public :: link_file, folder_files, folder_name, canonical_path

    integer(c_int), parameter :: f_ok = 0          !! access(2): the path exists
    integer(c_int), parameter :: mode_rwx = 511    !! mkdir(2): 0777, less the umask
    integer, parameter :: path_max = 4096          !! PATH_MAX on Linux

    !> glob(3)'s glob_t: the three fields POSIX names come first in glibc and musl
    !> (gl_pathc, gl_pathv, gl_offs); `rest` holds the others (glibc's glob_t is 72 bytes
    !> in all on 64-bit Linux) with room to spare.
    type, bind(C) :: glob_t
        integer(c_size_t) :: pathc = 0
        type(c_ptr) :: pathv = c_null_ptr
        integer(c_size_t) :: offs = 0
        integer(c_int64_t) :: rest(32) = 0
    end type glob_t

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

        integer(c_int) function c_link(from, to) bind(C, name='link')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: from(*), to(*)
        end function c_link

        integer(c_int) function c_glob(pattern, flags, errfunc, pglob) bind(C, name='glob')
            import :: c_int, c_char, c_funptr, glob_t
            character(kind=c_char), intent(in) :: pattern(*)
            integer(c_int), value :: flags
            type(c_funptr), value :: errfunc
            type(glob_t), intent(inout) :: pglob
        end function c_glob

        subroutine c_globfree(pglob) bind(C, name='globfree')
            import :: glob_t
            type(glob_t), intent(inout) :: pglob
        end subroutine c_globfree

        integer(c_size_t) function c_strlen(text) bind(C, name='strlen')
            import :: c_size_t, c_ptr
            type(c_ptr), value :: text
        end function c_strlen
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

    !> A second name `to` for the file `from` (link(2)): fails, leaving `to` as it was, when
    !> `to` exists.
    subroutine link_file(from, to, error)
        character(len=*), intent(in) :: from, to
        type(error_t), allocatable, intent(out) :: error
        if (c_link(from//c_null_char, to//c_null_char) /= 0) then
            call fatal_error(error, 'cannot link '//from//' to '//to, io_error)
        end if
    end subroutine link_file

    !> The names (without the folder) of the files and folders in `folder` whose names do
    !> not start with '.', sorted (glob(3) of FOLDER/*); none when it cannot be read.
    subroutine folder_files(folder, names)
        character(len=*), intent(in) :: folder
        character(len=:), allocatable, intent(out) :: names(:)
        character(len=*), parameter :: special = '*?['//achar(92)
        character(len=:), allocatable :: prefix, pattern, name
        type(glob_t) :: found
        type(c_ptr), pointer :: paths(:)
        character(kind=c_char), pointer :: chars(:)
        integer :: k, n, width
        prefix = folder
        if (len(prefix) == 0) prefix = '.'
        if (prefix(len(prefix):) /= '/') prefix = prefix//'/'
        ! The folder's own name taken literally: its pattern characters escaped.
        pattern = ''
        do k = 1, len(prefix)
            if (index(special, prefix(k:k)) > 0) pattern = pattern//achar(92)
            pattern = pattern//prefix(k:k)
        end do
        pattern = pattern//'*'
        allocate (character(len=1) :: names(0))
        if (c_glob(pattern//c_null_char, 0_c_int, c_null_funptr, found) /= 0) then
            call c_globfree(found)
            return
        end if
        n = int(found%pathc)
        call c_f_pointer(found%pathv, paths, [n])
        width = 1
        do k = 1, n
            width = max(width, int(c_strlen(paths(k))) - len(prefix))
        end do
        deallocate (names)
        allocate (character(len=width) :: names(n))
        do k = 1, n
            call c_f_pointer(paths(k), chars, [int(c_strlen(paths(k)))])
            allocate (character(len=size(chars)) :: name)
            name = transfer(chars, name)
            names(k) = name(len(prefix) + 1:)
            deallocate (name)
        end do
        call c_globfree(found)
    end subroutine folder_files

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

    !> A path in the form two names of one file compare equal: its folder resolved
    !> (realpath(3)), then its last component as given, so that a link named as a result
    !> file is that name and not its target (a rename replaces the link, not the target).
    function canonical_path(path) result(canonical)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: canonical
        canonical = resolved_path(folder_name(path))
        if (canonical(len(canonical):) /= '/') canonical = canonical//'/'
        canonical = canonical//base_name(path)
    end function canonical_path

    !> The folder of a path: 'inputs/dam.dat' -> 'inputs', 'dam.dat' -> '.', '/dam' -> '/'.
    pure function folder_name(path) result(folder)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: folder
        integer :: slash
        slash = index(path, '/', back=.true.)
        if (slash == 0) then
            folder = '.'
        else if (slash == 1) then
            folder = '/'
        else
            folder = path(:slash - 1)
        end if
    end function folder_name

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
