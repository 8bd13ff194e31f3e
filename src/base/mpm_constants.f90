!> Mathematical constants, exit codes, version, fixed limits.
! SPDX-License-Identifier: MIT
module mpm_constants
  use mpm_kinds, only: wp
  implicit none
  private
  public :: pi, version_string, EXIT_OK, EXIT_INTERNAL, EXIT_INPUT, EXIT_IO, EXIT_NUMERIC, &
            name_len, path_len, msg_len, max_table
  public :: BASIS_LINEAR, BASIS_UGIMP, BASIS_CPDI1, BASIS_CPDI2, basis_names
  public :: SCHEME_USL, SCHEME_USF, SCHEME_MUSL, scheme_names
  public :: PLANE_STRAIN, PLANE_STRESS, plane_names
  public :: VOLUMETRIC_STANDARD, VOLUMETRIC_FBAR, VOLUMETRIC_FBARWALL, volumetric_names
  public :: MODEL_ELASTIC, MODEL_NEOHOOKEAN, MODEL_J2, MODEL_FOAM, model_names
  public :: RATE_NONE, RATE_COWPER_SYMONDS, rate_law_names
  public :: FLOW_LINEAR, FLOW_JOHNSON_COOK, flow_stress_names
  public :: SHAPE_RING, SHAPE_RECT, SHAPE_TUBE, SHAPE_HONEYCOMB, SHAPE_WALLS, SHAPE_DISC, &
            SHAPE_FILLER, &
            shape_names, shape_plural, max_vertices, max_cells
  public :: SECTOR_FULL, SECTOR_HALF, SECTOR_QUARTER, sector_names
  public :: CONTACT_FRICTIONLESS, CONTACT_COULOMB, CONTACT_STICK, CONTACT_SLIP, CONTACT_BONDED, &
            contact_names

  real(wp), parameter :: pi = 3.141592653589793_wp
  character(len=*), parameter :: version_string = '0.1.0'

  integer, parameter :: EXIT_OK = 0         !! success
  integer, parameter :: EXIT_INTERNAL = 1   !! bug in tubempm
  integer, parameter :: EXIT_INPUT = 2      !! bad command line or namelist
  integer, parameter :: EXIT_IO = 3         !! file could not be read or written
  integer, parameter :: EXIT_NUMERIC = 4    !! numerical failure detected

  integer, parameter :: name_len = 64       !! length of names and enumeration values
  integer, parameter :: path_len = 512      !! length of file paths
  integer, parameter :: msg_len = 4096      !! length of error messages (may hold several lines)
  integer, parameter :: max_table = 64      !! points of a wall motion table, a foam curve

  ! Enumerations of the namelist input: the integer code is the index into the names array.
  integer, parameter :: BASIS_LINEAR = 1, BASIS_UGIMP = 2, BASIS_CPDI1 = 3, BASIS_CPDI2 = 4
  character(len=*), parameter :: basis_names(4) = [character(len=6) :: &
    'linear', 'ugimp', 'cpdi1', 'cpdi2']
  integer, parameter :: SCHEME_USL = 1, SCHEME_USF = 2, SCHEME_MUSL = 3
  character(len=*), parameter :: scheme_names(3) = [character(len=4) :: 'usl', 'usf', 'musl']
  integer, parameter :: PLANE_STRAIN = 1, PLANE_STRESS = 2
  character(len=*), parameter :: plane_names(2) = [character(len=6) :: 'strain', 'stress']
  integer, parameter :: VOLUMETRIC_STANDARD = 1, VOLUMETRIC_FBAR = 2, VOLUMETRIC_FBARWALL = 3
  character(len=*), parameter :: volumetric_names(3) = [character(len=8) :: 'standard', 'fbar', &
                                                        'fbarwall']
  integer, parameter :: MODEL_ELASTIC = 1, MODEL_NEOHOOKEAN = 2, MODEL_J2 = 3, MODEL_FOAM = 4
  character(len=*), parameter :: model_names(4) = [character(len=10) :: &
    'elastic', 'neohookean', 'j2', 'foam']
  integer, parameter :: RATE_NONE = 1, RATE_COWPER_SYMONDS = 2
  character(len=*), parameter :: rate_law_names(2) = [character(len=14) :: &
    'none', 'cowper_symonds']
  integer, parameter :: FLOW_LINEAR = 1, FLOW_JOHNSON_COOK = 2
  character(len=*), parameter :: flow_stress_names(2) = [character(len=12) :: &
    'linear', 'johnson_cook']
  integer, parameter :: SHAPE_RING = 1, SHAPE_RECT = 2, SHAPE_TUBE = 3, SHAPE_HONEYCOMB = 4, &
                        SHAPE_WALLS = 5, SHAPE_DISC = 6, SHAPE_FILLER = 7
  character(len=*), parameter :: shape_names(7) = [character(len=9) :: 'ring', 'rect', 'tube', &
    'honeycomb', 'walls', 'disc', 'filler']
  character(len=*), parameter :: shape_plural(7) = [character(len=10) :: 'rings', 'rectangles', &
    'tubes', 'honeycombs', 'wall sets', 'discs', 'fillers']
  integer, parameter :: max_vertices = 64  !! vertices of a 'tube'
  integer, parameter :: max_cells = 64     !! cells of a 'honeycomb' along x and along y
  integer, parameter :: SECTOR_FULL = 1, SECTOR_HALF = 2, SECTOR_QUARTER = 3
  character(len=*), parameter :: sector_names(3) = [character(len=7) :: &
    'full', 'half', 'quarter']
  integer, parameter :: CONTACT_FRICTIONLESS = 1, CONTACT_COULOMB = 2, CONTACT_STICK = 3, &
                        CONTACT_SLIP = 4, CONTACT_BONDED = 5
  character(len=*), parameter :: contact_names(5) = [character(len=12) :: &
    'frictionless', 'coulomb', 'stick', 'slip', 'bonded']
end module mpm_constants
