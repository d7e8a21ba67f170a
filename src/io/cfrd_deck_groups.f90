!> The groups of a deck (docs/cards.md): their keywords, the cards sorted under each, the
!> counts of the CONTROL card, and the checks shared by the group readers.
module cfrd_deck_groups
    use cfrd_error, only: error_t, fatal_error, input_error
    use cfrd_cards, only: card_t, upper, to_text
    implicit none
    private

    public :: group_cards_t, counts_t, append_card, leading_word, check_numbering
    public :: g_title, g_control, g_nodes, g_elements, g_materials, g_boundary, g_loads, &
              g_stages, g_reservoir, g_gauges, g_interface, g_slab, g_contact, g_plinth, ngroups
    public :: group_keywords, valid_groups, group_required, load_keywords, stage_keywords, &
              contact_keywords, effects_keyword, errctl_keyword, creep_keyword, wetting_keyword, &
              max_number

    integer, parameter :: g_title = 1, g_control = 2, g_nodes = 3, g_elements = 4, &
                          g_materials = 5, g_boundary = 6, g_loads = 7, g_stages = 8, &
                          g_reservoir = 9, g_gauges = 10, g_interface = 11, g_slab = 12, &
                          g_contact = 13, g_plinth = 14, ngroups = 14
    character(len=10), parameter :: group_keywords(ngroups) = [character(len=10) :: &
                                    'TITLE', 'CONTROL', 'NODES', 'ELEMENTS', 'MATERIALS', &
                                    'BOUNDARY', 'LOADS', 'STAGES', 'RESERVOIR', 'GAUGES', &
                                    'INTERFACE', 'SLAB', 'CONTACT', 'PLINTH']
    character(len=*), parameter :: valid_groups = 'TITLE, CONTROL, NODES, ELEMENTS, '// &
                                   'MATERIALS, BOUNDARY, LOADS, STAGES, RESERVOIR, GAUGES, '// &
                                   'INTERFACE, SLAB, CONTACT, PLINTH, END'
    logical, parameter :: group_required(ngroups) = [.false., .false., .true., .true., &
                                                     .true., .true., .false., .false., &
                                                     .false., .false., .false., .false., &
                                                     .false., .false.]
    character(len=10), parameter :: load_keywords(3) = [character(len=10) :: 'GRAVITY', &
                                                        'FORCE', 'PRESSURE']
    character(len=10), parameter :: stage_keywords(6) = [character(len=10) :: 'FILL', &
                                                         'LOAD', 'RESET', 'WATER', 'WAIT', &
                                                         'WET']
    character(len=10), parameter :: contact_keywords(2) = [character(len=10) :: 'SURFACE', &
                                                           'PAIR']
    !> The card of CONTROL that lists the effects a deck asks for.
    character(len=*), parameter :: effects_keyword = 'EFFECTS'
    !> The card of CONTROL that sets the error control of midpoint and Euler increments.
    character(len=*), parameter :: errctl_keyword = 'ERRCTL'
    !> The card of MATERIALS that gives an EB material its creep (after its two cards).
    character(len=*), parameter :: creep_keyword = 'CREEP'
    !> ... and its wetting collapse (WETTING, after the two cards or the CREEP card).
    character(len=*), parameter :: wetting_keyword = 'WETTING'

    !> Largest node or element number accepted when the CONTROL card gives no count
    !> (guards against a mistyped number allocating gigabytes).
    integer, parameter :: max_number = 10000000

    !> The cards of one group, in deck order.
    type :: group_cards_t
        character(len=10) :: name = ''     !! LOADS groups: the load set's name
        logical :: present = .false.
        integer :: header_line = 0
        integer :: n = 0
        type(card_t), allocatable :: cards(:)
    end type group_cards_t

    !> Counts announced on the CONTROL card (0 = not given) and where they stand.
    type :: counts_t
        integer :: nnode = 0, nelem = 0, nmat = 0
        integer :: line = 0
    end type counts_t

contains

    !> The upper-case word that starts a card (columns 1-10, or the first free token) when it
    !> starts with a letter; '' otherwise.
    function leading_word(card) result(word)
        type(card_t), intent(in) :: card
        character(len=:), allocatable :: word
        character(len=:), allocatable :: head
        if (card%free) then
            head = card%text(card%token_first(1):max(card%token_last(1), &
                                                     card%token_first(1) - 1))
        else
            head = card%text(1:min(10, len(card%text)))
        end if
        word = trim(adjustl(upper(head)))
        if (len(word) == 0) return
        if (index(word, ' ') > 0) word = word(1:index(word, ' ') - 1)
        if (.not. ((word(1:1) >= 'A' .and. word(1:1) <= 'Z'))) word = ''
        if (len(word) == 0 .or. card%free) return
        ! Headers are left-justified. An indented keyword is still taken as one, but any other
        ! indented word is data: '       inf' in an F10 field deserves a field error, not
        ! "unknown group 'INF'".
        if (card%text(1:1) == ' ' .and. .not. (word == 'END' .or. word == 'STOP' .or. &
            any(group_keywords == word) .or. any(load_keywords == word) .or. &
            any(stage_keywords == word) .or. any(contact_keywords == word) .or. &
            word == effects_keyword .or. word == errctl_keyword .or. &
            word == creep_keyword .or. word == wetting_keyword)) word = ''
    end function leading_word

    subroutine append_card(group, card)
        type(group_cards_t), intent(inout) :: group
        type(card_t), intent(in) :: card
        type(card_t), allocatable :: grown(:)
        if (.not. allocated(group%cards)) allocate (group%cards(64))
        if (group%n == size(group%cards)) then
            allocate (grown(2*group%n))
            grown(1:group%n) = group%cards(1:group%n)
            call move_alloc(grown, group%cards)
        end if
        group%n = group%n + 1
        group%cards(group%n) = card
    end subroutine append_card

    !> Numbers 1..n with none missing, and n equal to the CONTROL count when one was given.
    subroutine check_numbering(file, header_line, what, defined_line, announced, count_name, &
                               control_line, error)
        character(len=*), intent(in) :: file, what, count_name
        integer, intent(in) :: header_line, defined_line(:), announced, control_line
        type(error_t), allocatable, intent(out) :: error
        integer :: missing
        missing = findloc(defined_line, 0, dim=1)
        if (missing > 0) then
            call fatal_error(error, file//':'//to_text(header_line)//': missing '//what//' '// &
                             to_text(missing)//' ('//what//'s must be numbered 1 to '// &
                             to_text(size(defined_line))//' without gaps)', input_error)
            return
        end if
        if (announced > 0 .and. announced /= size(defined_line)) then
            call fatal_error(error, file//':'//to_text(control_line)//': field '//count_name// &
                             ' of CONTROL: '//to_text(announced)//' '//what// &
                             's announced, '//to_text(size(defined_line))//' read', input_error)
        end if
    end subroutine check_numbering
end module cfrd_deck_groups
