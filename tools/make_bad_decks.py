#!/usr/bin/env python3
"""Writes the bad decks of test/bad_decks/ (run from the repository root).

Each case mutates one small valid deck; its first card `* expect: ...` holds the message
fragment that the card manual (docs/cards.md) promises for that mistake, which
tools/run_tests.sh asserts together with exit status 2.
"""
import os
base = """TITLE     bad deck
CONTROL
    6    2    1
NODES
    1    3    1       0.0       0.0       2.0       0.0
    4    6    1       0.0       1.0       2.0       1.0
ELEMENTS
    1    1    2    5    4    1    1    1 SOIL
MATERIALS
    1ELASTIC   soil
   20000.0       0.3      20.0
BOUNDARY
    1    3    1    1    1
LOADS
GRAVITY
END
"""
# line numbers (with the expect card as line 1): TITLE 2, CONTROL 3, counts 4, NODES 5,
# node cards 6-7, ELEMENTS 8, element 9, MATERIALS 10, mat 11-12, BOUNDARY 13, bc 14,
# LOADS 15, GRAVITY 16, END 17
def editor(deck):
    """A function (old, new) -> the deck with its first `old` replaced by `new`."""
    def sub(old, new):
        assert old in deck, old
        return deck.replace(old, new, 1)
    return sub


sub = editor(base)
P = "test/bad_decks/"
cases = [
 ("unknown-group", sub("LOADS\n", "LODES\n"), "{f}:15: unknown group 'LODES'"),
 ("missing-nodes", sub("NODES\n    1    3    1       0.0       0.0       2.0       0.0\n    4    6    1       0.0       1.0       2.0       1.0\n", ""), "{f}: missing group NODES"),
 ("missing-boundary", sub("BOUNDARY\n    1    3    1    1    1\n", ""), "{f}: missing group BOUNDARY"),
 ("missing-materials", sub("MATERIALS\n    1ELASTIC   soil\n   20000.0       0.3      20.0\n", ""), "{f}: missing group MATERIALS"),
 ("missing-elements", sub("ELEMENTS\n    1    1    2    5    4    1    1    1 SOIL\n", ""), "{f}: missing group ELEMENTS"),
 ("duplicate-group", sub("LOADS\n", "NODES\nLOADS\n"), "{f}:15: duplicate group NODES (first at line 5)"),
 ("no-end", sub("END\n", ""), "{f}: no END card: is the deck truncated?"),
 ("card-before-header", "    1    2\n" + base, "{f}:2: data card before any group header"),
 ("integer-not-numeric", sub("    1    3    1       0.0", "   1x    3    1       0.0"), "{f}:6:1-5: field N1 of NODES: expected an integer, found '1x'"),
 ("real-not-numeric", sub("       2.0       0.0\n    4", "       abc       0.0\n    4"), "{f}:6:36-45: field X2 of NODES 1: expected a real number, found 'abc'"),
 ("embedded-blank", sub("   20000.0       0.3", "  2000 0.0       0.3"), "{f}:12:1-10: field E of MATERIALS 1: expected a real number, found '2000 0.0'"),
 ("real-in-integer-field", sub("    4    6    1       0.0", "  4.0    6    1       0.0"), "{f}:7:1-5: field N1 of NODES: expected an integer, found '4.0'"),
 ("negative-modulus", sub("   20000.0       0.3", "  -20000.0       0.3"), "{f}:12:1-10: field E of MATERIALS 1: expected a real > 0 (kPa), found '-20000.0'"),
 ("poisson-half", sub("   20000.0       0.3", "   20000.0       0.5"), "{f}:12:11-20: field NU of MATERIALS 1: expected a real with 0 <= NU < 0.5, found '0.5'"),
 ("nnode-mismatch", sub("    6    2    1\n", "    7    2    1\n"), "{f}:4: field NNODE of CONTROL: 7 nodes announced, 6 read"),
 ("nelem-mismatch", sub("    6    2    1\n", "    6    3    1\n"), "{f}:4: field NELEM of CONTROL: 3 elements announced, 2 read"),
 ("nmat-mismatch", sub("    6    2    1\n", "    6    2    2\n"), "{f}:4: field NMAT of CONTROL: 2 materials announced, 1 read"),
 ("duplicate-node", sub("ELEMENTS\n", "    3" + " "*10 + "       2.0       0.0\nELEMENTS\n"), "{f}:8: duplicate node 3 (first defined at line 6)"),
 ("missing-node", sub("    4    6    1       0.0       1.0       2.0       1.0\n", "    5    6    1       1.0       1.0       2.0       1.0\n"), "{f}:5: missing node 4 (nodes must be numbered 1 to 6 without gaps)"),
 ("element-missing-node", sub("    1    1    2    5    4    1    1", "    1    1    2    9    4    1    1"), "{f}:9:16-20: field K of ELEMENTS 1: expected a node from 1 to 6"),
 ("repeated-node", sub("    1    1    2    5    4    1    1", "    1    1    2    2    4    1    1"), "{f}:9: element 1 repeats a node"),
 ("inverted-element", sub("    1    1    2    5    4    1    1", "    1    1    4    5    2    1    1"), "{f}:9: element 1 is inverted"),
 ("degenerate-element", sub("    4    6    1       0.0       1.0       2.0       1.0", "    4    6    1       3.0       0.0       5.0       0.0"), "{f}:9: element 1 is degenerate"),
 ("material-out-of-range", sub("    1    1    2    5    4    1    1", "    1    1    2    5    4    2    1"), "{f}:9:26-30: field MAT of ELEMENTS 1: expected a material number from 1 to 1, found '2'"),
 ("missing-material-card", sub("   20000.0       0.3      20.0\n", ""), "{f}:11: MATERIALS 1: missing parameter card (E, NU, GAMMA)"),
 ("unknown-law", sub("    1ELASTIC", "    1PLASTIC"), "{f}:11:6-15: field LAW of MATERIALS 1: expected a material law: ELASTIC, EB, GOODMAN or PJOINT, found 'PLASTIC'"),
 ("unused-node", sub("    6    2    1\n", "         2    1\n").replace("ELEMENTS\n", "    7" + " "*10 + "       9.0       9.0\nELEMENTS\n"), "{f}:8: node 7 is used by no element"),
 ("rigid-no-x", sub("    1    3    1    1    1\n", "    1    3    1    0    1\n"), "{f}:13: rigid-body motion not suppressed: translation in x is free"),
 ("rigid-rotation", sub("    1    3    1    1    1\n", "    1" + " "*10 + "    1    1\n"), "{f}:13: rigid-body motion not suppressed: rotation is free"),
 ("boundary-fixes-nothing", sub("    1    3    1    1    1\n", "    1    3    1    1    1\n    4              0    0\n"), "{f}:15: BOUNDARY card fixes nothing"),
 ("unknown-load", sub("GRAVITY\n", "WIND      \n"), "{f}:16: unknown load 'WIND' in LOADS"),
 ("unknown-gravity-group", sub("GRAVITY\n", "GRAVITY   ROCK\n"), "{f}:16:11-20: field GROUP of GRAVITY: expected ALL or an element group (SOIL), found 'ROCK'"),
 ("pressure-face", sub("GRAVITY\n", "PRESSURE      1    5     100.0\n"), "{f}:16:16-20: field FACE of PRESSURE: expected a face from 1 to 4, found '5'"),
 ("pressure-triangle-face3", sub("    1    1    2    5    4    1    1", "    1    1    2    5    5    1    1").replace("GRAVITY\n", "PRESSURE      1    3     100.0\n"), "{f}:16:16-20: field FACE of PRESSURE: expected face 1, 2 or 4: element 1 is a triangle"),
 ("beyond-column-80", sub("    1    3    1       0.0       0.0       2.0       0.0\n", "    1    3    1       0.0       0.0       2.0       0.0" + " "*25 + "extra\n"), "{f}:6:81-85: text beyond column 80"),
 ("tab-character", sub("    1    3    1       0.0", "    1    3    1\t0.0"), "{f}:6:16-16: a tab character on a fixed-format card"),
 ("units", sub("    6    2    1\n", "    6    2    1" + " "*25 + "KIP-FT\n"), "{f}:4:41-50: field UNITS of CONTROL: expected KN-M (m, kN, kPa) or blank, found 'KIP-FT'"),
 ("model-type", sub("    6    2    1\n", "    6    2    1    3\n"), "{f}:4:16-20: field MODEL of CONTROL: expected 1 (plane strain) or 2 (axisymmetric), found '3'"),
 ("increment-not-divisor", sub("    1    3    1       0.0", "    1    3    3       0.0"), "{f}:6:11-15: field INC of NODES: expected an increment that divides N2 - N1 = 2, found '3'"),
 ("free-format-bad-real", sub("    1    3    1       0.0       0.0       2.0       0.0", "&1, 3, 1, 0.0, zero, 2.0, 0.0"), "{f}:6:16-19: field Y1 of NODES 1: expected a real number, found 'zero'"),
 ("duplicate-element", sub("ELEMENTS\n    1    1    2    5    4    1    1    1 SOIL\n", "ELEMENTS\n    1    1    2    5    4    1    1    1 SOIL\n    2    2    3    6    5    1\n"), "{f}:10: duplicate element 2 (first defined at line 9)"),
 ("missing-element", sub("    6    2    1\n", "    6         1\n").replace("    1    1    2    5    4    1    1    1 SOIL\n", "    1    1    2    5    4    1\n    3    2    3    6    5    1\n"), "{f}:8: missing element 2 (elements must be numbered 1 to 3 without gaps)"),
 ("duplicate-material", sub("BOUNDARY\n", "    1ELASTIC   again\n   30000.0       0.3      20.0\nBOUNDARY\n"), "{f}:13: duplicate material 1 (first defined at line 11)"),
 ("title-data-card", sub("TITLE     bad deck\n", "TITLE     bad deck\n    1\n"), "{f}:3: TITLE takes no data cards"),
 ("control-two-cards", sub("    6    2    1\n", "    6    2    1\n    6    2    1\n"), "{f}:5: CONTROL takes one card of numbers and one EFFECTS card (the card of numbers is at line 4)"),
 ("value-without-code", sub("    1    3    1    1    1\n", "    1    3    1    0    1       0.1\n"), "{f}:14:26-35: field UX of BOUNDARY 1: expected blank: a prescribed value needs IX = 1, found '0.1'"),
 ("unknown-load-set", sub("GRAVITY\n", "GRAVITY\nSTAGES\n&LOAD, WIND\n"), "{f}:18:8-11: field SET of STAGES LOAD: expected blank (the unnamed LOADS) or the name of a LOADS group, found 'WIND'"),
 ("unknown-fill-group", sub("GRAVITY\n", "GRAVITY\nSTAGES\nFILL      ROCK\n"), "{f}:18:11-20: field GROUP of STAGES FILL: expected an element group (SOIL), found 'ROCK'"),
 ("pressure-before-fill", sub("GRAVITY\n", "PRESSURE      2    2     100.0\nSTAGES\nLOAD\nFILL      SOIL\n"), "{f}:18: stage 1 (LOAD): PRESSURE on element 2, which is not placed yet"),
 ("node-beyond-nnode", sub("    4    6    1       0.0", "    4    8    2       0.0"), "{f}:7:6-10: field N2 of NODES: expected a last node from N1 = 4 to 6, found '8'"),
 ("real-overflow", sub("   20000.0       0.3", "     1e999       0.3"), "{f}:12:1-10: field E of MATERIALS 1: expected a real number of magnitude below 1e20, found '1e999'"),
 ("indented-word", sub("   20000.0       0.3", "       inf       0.3"), "{f}:12:1-10: field E of MATERIALS 1: expected a real number, found 'inf'"),
 ("free-extra-field", sub("    1    3    1       0.0       0.0       2.0       0.0", "&1, 3, 1, 0.0, 0.0, 2.0, 0.0, 7"), "{f}:6:31-31: field after Y2 of NODES: expected no more fields (the card has 7), found '7'"),
 ("lone-ampersand", sub("    1    3    1       0.0       0.0       2.0       0.0", "&\n    1    3    1       0.0       0.0       2.0       0.0"), "{f}:6:2-2: field N1 of NODES"),
 ("water-without-reservoir", sub("GRAVITY\n", "GRAVITY\nSTAGES\nLOAD\nWATER          10.0\n"), "{f}:19: WATER stage, but the deck has no RESERVOIR faces"),
 ("water-without-level", sub("GRAVITY\n", "GRAVITY\nRESERVOIR\n    1    4\nSTAGES\nLOAD\nWATER\n"), "{f}:21:11-20: field LEVEL of STAGES WATER: expected the reservoir level to reach (m), found ''"),
 ("reservoir-face", sub("GRAVITY\n", "GRAVITY\nRESERVOIR\n    1    6\n"), "{f}:18:6-10: field FACE of RESERVOIR 1: expected a face from 1 to 4, found '6'"),
 ("reservoir-element", sub("GRAVITY\n", "GRAVITY\nRESERVOIR\n    3    4\n"), "{f}:18:1-5: field ELEM of RESERVOIR: expected an element from 1 to 2, found '3'"),
 ("reservoir-cover-group", sub("GRAVITY\n", "GRAVITY\nRESERVOIR\n    1    4SLAB\n"), "{f}:18:11-20: field COVER of RESERVOIR 1: expected blank or an element group (SOIL), found 'SLAB'"),
 ("reservoir-twice", sub("GRAVITY\n", "GRAVITY\nRESERVOIR\n    1    4\n    1    4\n"), "{f}:19: face 4 of element 1 is wetted twice (first at line 18)"),
 ("gauge-node", sub("GRAVITY\n", "GRAVITY\nGAUGES\n    9 C1-H5\n"), "{f}:18:1-5: field NODE of GAUGES: expected a node from 1 to 6, found '9'"),
 ("gauge-name-twice", sub("GRAVITY\n", "GRAVITY\nGAUGES\n    5 C1-H5\n    6 c1-h5\n"), "{f}:19:6-15: field NAME of GAUGES 6: expected a name not used before (line 18), found 'c1-h5'"),
 ("unknown-stage", sub("GRAVITY\n", "GRAVITY\nSTAGES\nFLOOD\n"), "{f}:18: unknown stage 'FLOOD' in STAGES: expected FILL, LOAD, RESET, WATER, WAIT or WET"),
]
# A joint deck: two blocks (nodes 1-6 and 7-12) joined by joints between nodes 4-6 and 7-9.
jbase = """TITLE     bad joint deck
NODES
    1    3    1       0.0       0.0       2.0       0.0
    4    6    1       0.0       1.0       2.0       1.0
    7    9    1       0.0       1.0       2.0       1.0
   10   12    1       0.0       2.0       2.0       2.0
ELEMENTS
    1    1    2    5    4    1    1    1
    3    7    8   11   10    1    1    1 SLAB
MATERIALS
    1ELASTIC   block
     1.0E6       0.2      20.0
    2GOODMAN   joint
     1.0E7     1.0E4      1000       0.3       1.0      30.0
INTERFACE
    1    4    7    2    1    1    2JOINT     LOBATTO   SLAB
BOUNDARY
    1    3    1    1    1
LOADS
GRAVITY
END
"""
# lines: TITLE 2, NODES 3, nodes 4-7, ELEMENTS 8, elements 9-10, MATERIALS 11, 12-15,
# INTERFACE 16, pair card 17, BOUNDARY 18, 19, LOADS 20, GRAVITY 21, END 22
jsub = editor(jbase)
PAIR = "    1    4    7    2    1    1    2JOINT     LOBATTO   SLAB"
cases += [
 ("goodman-missing-knt", jsub("     1.0E7     1.0E4", "     1.0E7          "), "{f}:15:11-20: field KNT of MATERIALS 2: expected a real > 0 (kPa/m), found ''"),
 ("goodman-cutoff", jsub("      30.0\n", "      30.0" + " " * 10 + "    2\n"), "{f}:15:71-75: field CUTOFF of MATERIALS 2: expected 0 (tension carried with KNT) or 1 (tension cut-off), found '2'"),
 ("goodman-on-element", jsub("    1    1    2    5    4    1    1    1\n", "    1    1    2    5    4    2    1    1\n"), "{f}:9:26-30: field MAT of ELEMENTS 1: expected a solid material: GOODMAN is the law of joints, given on INTERFACE cards, found '2'"),
 ("interface-type", jsub("JOINT     LOBATTO", "GLUE      LOBATTO"), "{f}:17:36-45: field TYPE of INTERFACE line 1: expected an interface type: JOINT or THIN, found 'GLUE'"),
 ("interface-rule", jsub("JOINT     LOBATTO", "JOINT     SIMPSON"), "{f}:17:46-55: field RULE of INTERFACE line 1: expected an integration rule: GAUSS or LOBATTO"),
 ("joint-elastic-material", jsub(PAIR, PAIR.replace("    2JOINT", "    1JOINT")), "{f}:17:31-35: field MAT of INTERFACE line 1: expected a GOODMAN or PJOINT material for a JOINT, found '1'"),
 ("thin-goodman-material", jsub("JOINT     LOBATTO", "THIN              "), "{f}:17:31-35: field MAT of INTERFACE line 1: expected a solid material (not a joint) for THIN, found '2'"),
 ("joint-gap", jsub("    7    9    1       0.0       1.0       2.0       1.0", "    7    9    1       0.0       1.1       2.0       1.1"), "{f}:17:11-15: field NT of INTERFACE line 1: expected a top node at its bottom node (pair 4/7: the nodes are 1.000E-01 m apart; a JOINT has zero thickness, use THIN for a layer), found '7'"),
 ("joint-orientation", jsub(PAIR, "    1    6    9    2   -1   -1    2JOINT     LOBATTO   SLAB"), "{f}:17: INTERFACE line 1, pairs 6/9 and 5/8: the top nodes' elements lie on the right of the line from bottom node 6 to 5; list the pairs of the line in the opposite order"),
 ("interface-one-pair", jsub(PAIR, PAIR.replace("    1    4    7    2", "    1    4    7    0")), "{f}:17: INTERFACE line 1 has one node pair"),
 ("interface-node", jsub(PAIR, PAIR.replace("    1    4    7    2", "    1    4   17    2")), "{f}:17:11-15: field NT of INTERFACE line 1: expected a node from 1 to 12 for every generated pair, found '17'"),
 ("pressure-on-joint", jsub("GRAVITY\n", "PRESSURE      5    1     100.0\n"), "{f}:21:11-15: field ELEM of PRESSURE: expected a solid element (element 5 is a joint, which has no faces to load), found '5'"),
 ("slab-group", jsub("BOUNDARY\n", "SLAB\n          FACE\nBOUNDARY\n"), "{f}:19:11-20: field GROUP of SLAB: expected an element group (SLAB), found 'FACE'"),
]
cbase = """TITLE     bad contact deck
NODES
    1    3    1       0.0       0.0       2.0       0.0
    4    6    1       0.0       1.0       2.0       1.0
    7   10    1       0.0       1.0       2.0       1.0
   11   14    1       0.0       2.0       2.0       2.0
ELEMENTS
    1    1    2    5    4    1    1    1
    3    7    8   12   11    1    2    1 TOP
MATERIALS
    1ELASTIC   block
     1.0E6       0.2      20.0
CONTACT
SURFACE   TOP           3    1    2    1
SURFACE   BASE          1    3    1    1
PAIR      TOP       BASE           0.5
BOUNDARY
    1    3    1    1    1
LOADS
GRAVITY
END
"""
# lines: TITLE 2, NODES 3, nodes 4-7, ELEMENTS 8, elements 9-10, MATERIALS 11, 12-13,
# CONTACT 14, SURFACE 15-16, PAIR 17, BOUNDARY 18, 19, LOADS 20, GRAVITY 21, END 22
csub = editor(cbase)
SURF = "SURFACE   BASE          1    3    1    1"
CPAIR = "PAIR      TOP       BASE           0.5"
cases += [
 ("contact-card", csub(SURF, SURF.replace("SURFACE ", "SURFAKE ")), "{f}:16: unknown card 'SURFAKE' in CONTACT: expected SURFACE or PAIR"),
 ("contact-face", csub(SURF, "SURFACE   BASE          1    5    1    1"), "{f}:16:26-30: field FACE of CONTACT SURFACE BASE: expected a face from 1 to 4, found '5'"),
 ("contact-element", csub(SURF, "SURFACE   BASE          9    3"), "{f}:16:21-25: field ELEM of CONTACT SURFACE BASE: expected elements from 1 to 5 (generated element 9 is not), found '9'"),
 ("contact-surface-name", csub(CPAIR, CPAIR.replace("BASE", "BASS")), "{f}:17:21-30: field MASTER of CONTACT PAIR: expected a surface named on a SURFACE card (TOP, BASE), found 'BASS'"),
 ("contact-shared-node", csub("SURFACE   TOP           3    1    2    1", "SURFACE   TOP           2    4"), "{f}:17: node 5 is on both surfaces TOP and BASE: contact is between independent bodies (give each its own nodes)"),
 ("contact-friction", csub(CPAIR, CPAIR.replace(" 0.5", "-0.5")), "{f}:17:31-40: field MU of CONTACT PAIR TOP: expected a real >= 0, found '-0.5'"),
 ("contact-scheme", csub(CPAIR, CPAIR.ljust(50) + "GLUE"), "{f}:17:51-60: field SCHEME of CONTACT PAIR TOP: expected MORTAR (segment-to-segment) or NTS (node-to-segment), found 'GLUE'"),
 ("contact-search", csub(CPAIR, CPAIR.ljust(50) + "MORTAR    SPLINE"), "{f}:17:61-70: field SEARCH of CONTACT PAIR TOP: expected LINEAR (piecewise-linear master surface) or RPIM (radial point interpolation), found 'SPLINE'"),
 ("contact-cast", csub(CPAIR, CPAIR.ljust(74) + "2"), "{f}:17:71-75: field CAST of CONTACT PAIR TOP: expected 0 or 1 (1: cast in place, the gap at placement counts as closed), found '2'"),
 ("element-type", csub("    3    7    8   12   11    1    2    1 TOP", "    3    7    8   12   11    1    2    1 TOP       Q8"), "{f}:10:51-60: field TYPE of ELEMENTS 3: expected an element type: Q4 (blank) or Q4S (assumed shear strain, for slabs in bending), found 'Q8'"),
 ("contact-unused-surface", csub(CPAIR, "SURFACE   SIDE          1    4\n" + CPAIR), "{f}:17: surface SIDE is in no CONTACT PAIR"),
]
# Found by tools/fuzz.py (issue 9, section 4): each crashed or misreported before its fix.
cases += [
 ("unit-weight-overflow", sub("   20000.0       0.3      20.0", "   20000.0       0.3     1e307"), "{f}:12:21-30: field GAMMA of MATERIALS 1: expected a real number of magnitude below 1e20, found '1e307'"),
 ("coordinate-overflow", sub("       2.0       0.0\n    4", "      1e12       0.0\n    4"), "{f}:6:36-45: field X2 of NODES 1: expected a coordinate of magnitude at most 1e7 (m), found '1e12'"),
 ("effects-word", sub("    6    2    1\n", "    6    2    1\nEFFECTS   NONLINEAR ON        MAYBE\n"), "{f}:5:31-40: field WATER of CONTROL EFFECTS: expected ON (the default, also blank) or OFF, found 'MAYBE'"),
 ("effects-twice", sub("    6    2    1\n", "    6    2    1\nEFFECTS   LINEAR\nEFFECTS             OFF\n"), "{f}:6: CONTROL takes one EFFECTS card (the first is at line 5)"),
 ("effects-phases", sub("    6    2    1\n", "    6    2    1\nEFFECTS" + " " * 63 + "OFF\n"), "{f}:5:71-80: field PHASES of CONTROL EFFECTS: expected an effect this deck can switch (PHASES OFF needs the SLAB cards that name the slab's element groups), found 'OFF'"),
]
# Time-dependent analysis (issue 19): the CREEP card of an EB material and the stage dates.
tbase = base.replace("    1ELASTIC   soil\n   20000.0       0.3      20.0\n",
                     "    1EB        rockfill\n      20.0     564.0      0.35      0.85     204.0"
                     "      0.18\n      51.0      13.0\n"
                     "CREEP         0.01     0.002       0.5     0.004       1.0\n").replace(
    "LOADS\nGRAVITY\n", "STAGES\nFILL      SOIL          11997-05-01\n"
                        "WAIT                    41998-05-01\n")
# lines: ... MATERIALS 10, EB cards 11-13, CREEP 14, BOUNDARY 15, bc 16, STAGES 17,
# FILL 18, WAIT 19, END 20
CREEP = "CREEP         0.01     0.002       0.5     0.004       1.0"
tsub = editor(tbase)
cases += [
 ("creep-not-eb", sub("   20000.0       0.3      20.0\n", "   20000.0       0.3      20.0\n" + CREEP + "\n"), "{f}:13: a CREEP card follows the two parameter cards of an EB material (MATERIALS 1 is not EB)"),
 ("creep-alpha-negative", tsub(CREEP, CREEP.replace("      0.01", "     -0.01")), "{f}:14:11-20: field ALPHA of MATERIALS 1 CREEP: expected a real with 0 < ALPHA <= 1 (1/day), found '-0.01'"),
 ("creep-b-absurd", tsub(CREEP, CREEP.replace("     0.002", "       0.2")), "{f}:14:21-30: field B of MATERIALS 1 CREEP: expected a real with 0 <= B <= 0.05, found '0.2'"),
 ("creep-exponent", tsub(CREEP, CREEP.replace("       1.0", "          ")), "{f}:14:51-60: field L of MATERIALS 1 CREEP: expected a real with 0 < L <= 3, found ''"),
 ("dates-backwards", tsub("WAIT                    41998-05-01", "WAIT                    41996-05-01"), "{f}:19:26-35: field DATE of STAGES WAIT: expected a date not before 1997-05-01 (line 18): stages go forwards in time, found '1996-05-01'"),
 ("wait-no-date", tsub("WAIT                    41998-05-01", "WAIT                    4"), "{f}:19:26-35: field DATE of STAGES WAIT: expected the date to wait until (WAIT needs a date), found ''"),
 ("creep-free-text-date", tsub("FILL      SOIL          11997-05-01", "FILL      SOIL          1May 1997"), "{f}:18:26-35: field DATE of STAGES FILL: expected a date YYYY-MM-DD, YYYY.MM or YYYY-MM, found 'May 1997'"),
 ("effects-creep-word", sub("    6    2    1\n", "    6    2    1\nEFFECTS" + " " * 73 + "NEVER\n"), "{f}:5:81-90: field CREEP of CONTROL EFFECTS: expected ON (the default, also blank) or OFF, found 'NEVER'"),
 ("date-impossible", tsub("WAIT                    41998-05-01", "WAIT                    41998-02-30"), "{f}:19:26-35: field DATE of STAGES WAIT: expected a date YYYY-MM-DD, YYYY.MM or YYYY-MM, found '1998-02-30'"),
]
# Wetting collapse (issue 19): the WETTING card of an EB material and the WET stage.
WETTING = "WETTING      0.003       0.6     0.004"
wsub = editor(tbase.replace(CREEP + "\n", CREEP + "\n" + WETTING + "\n", 1))
cases += [
 ("wetting-not-eb", sub("   20000.0       0.3      20.0\n", "   20000.0       0.3      20.0\n" + WETTING + "\n"), "{f}:13: a WETTING card follows the two parameter cards of an EB material or its CREEP card (MATERIALS 1 is not EB)"),
 ("wetting-before-creep", tsub(CREEP + "\n", WETTING + "\n" + CREEP + "\n"), "{f}:15: a CREEP card follows the two parameter cards of an EB material (MATERIALS 1: CREEP before WETTING)"),
 ("wetting-cw-absurd", wsub(WETTING, WETTING.replace("     0.003", "       0.3")), "{f}:15:11-20: field CW of MATERIALS 1 WETTING: expected a real with 0 <= CW <= 0.05, found '0.3'"),
 ("wetting-nw-zero", wsub(WETTING, WETTING.replace("       0.6", "       0.0")), "{f}:15:21-30: field NW of MATERIALS 1 WETTING: expected a real with 0 < NW <= 3, found '0.0'"),
 ("wet-without-wetting", tsub("WAIT                    41998-05-01", "WET            690.0    41998-05-01"), "{f}:19: WET stage, but no material has a WETTING card (nothing would collapse)"),
 ("wet-level-word", wsub("WAIT                    41998-05-01", "WET             HIGH    41998-05-01"), "{f}:20:11-20: field LEVEL of STAGES WET: expected a real number, found 'HIGH'"),
]
# Bounds whose messages once stated others (issue 18): the message names the bound checked.
EB2 = "      20.0     564.0      0.35      0.85     204.0      0.18"
cases += [
 ("eb-n-bound", tsub(EB2, EB2.replace("      0.35", "    0.9995")), "{f}:12:21-30: field N of MATERIALS 1: expected a real with 0 <= N <= 0.999, found '0.9995'"),
 ("eb-m-bound", tsub(EB2, EB2.replace("      0.18", "   -0.9995")), "{f}:12:51-60: field M of MATERIALS 1: expected a real with -0.999 <= M <= 0.999, found '-0.9995'"),
 ("eb-phi0-bound", tsub("      51.0      13.0", "      89.5      13.0"), "{f}:13:1-10: field PHI0 of MATERIALS 1: expected an angle in degrees, 0 < PHI0 <= 89, found '89.5'"),
 ("eb-dphi-bound", tsub("      51.0      13.0", "      51.0      89.5"), "{f}:13:11-20: field DPHI of MATERIALS 1: expected an angle in degrees, 0 <= DPHI <= 89, found '89.5'"),
 ("goodman-n1-bound", jsub("      1000       0.3", "      1000    0.9995"), "{f}:15:31-40: field N1 of MATERIALS 2: expected a real with 0 <= N1 <= 0.999, found '0.9995'"),
 ("goodman-phi-bound", jsub("       1.0      30.0", "       1.0      89.5"), "{f}:15:51-60: field PHI of MATERIALS 2: expected an angle in degrees, 0 < PHI <= 89, found '89.5'"),
]
# The plinth and the perimetric joint (issue 22): a plinth quad on the rock (nodes 1-4), a
# slab quad on it (5-8) joined by a PJOINT line of one joint between pairs 3/5 and 4/6.
pbase = """TITLE     bad plinth deck
NODES
    1    2    1       0.0       0.0       2.0       0.0
    3    4    1       0.0       1.0       2.0       1.0
    5    6    1       0.0       1.0       2.0       1.0
    7    8    1       0.0       2.0       2.0       2.0
ELEMENTS
    1    1    2    4    3    1    0    1 PLINTH
    2    5    6    8    7    1    0    1 SLAB
MATERIALS
    1ELASTIC   concrete
     3.0E7       0.2      24.0
    2PJOINT    perimetric joint
     1.0E7     1.0E3     1.0E3
INTERFACE
    2    3    5    1    1    1    2JOINT     LOBATTO   SLAB
PLINTH
          PLINTH
BOUNDARY
    1    2    1    1    1
LOADS
GRAVITY
END
"""
# lines: TITLE 2, NODES 3, nodes 4-7, ELEMENTS 8, elements 9-10, MATERIALS 11, 12-15,
# INTERFACE 16, pair card 17, PLINTH 18, 19, BOUNDARY 20, 21, LOADS 22, GRAVITY 23, END 24
psub = editor(pbase)
cases += [
 ("pjoint-negative-stiffness", psub("     1.0E7     1.0E3     1.0E3", "     1.0E7    -1.0E3     1.0E3"), "{f}:15:11-20: field KNT of MATERIALS 2: expected a real > 0 (kPa/m), found '-1.0E3'"),
 ("pjoint-missing-ks", psub("     1.0E7     1.0E3     1.0E3", "     1.0E7     1.0E3"), "{f}:15:21-30: field KS of MATERIALS 2: expected a real > 0 (kPa/m), found ''"),
 ("plinth-not-on-base", psub("    2    5    6    8    7    1    0    1 SLAB", "    2    5    6    8    7    1    0    1 PLINTH"), "{f}:19:11-20: field GROUP of PLINTH: expected a group whose every element lies on the base (element 2 has no side whose two nodes BOUNDARY holds in x and y), found 'PLINTH'"),
 ("plinth-group", psub("          PLINTH\n", "          TOE\n"), "{f}:19:11-20: field GROUP of PLINTH: expected an element group (PLINTH, SLAB), found 'TOE'"),
 ("pjoint-nodes-apart", psub("    5    6    1       0.0       1.0       2.0       1.0", "    5    6    1       0.0      1.05       2.0      1.05"), "{f}:17:11-15: field NT of INTERFACE line 2: expected a top node at its bottom node (pair 3/5: the nodes are 5.000E-02 m apart; a JOINT has zero thickness, use THIN for a layer), found '5'"),
 ("pjoint-on-element", psub("    1    1    2    4    3    1    0    1 PLINTH", "    1    1    2    4    3    2    0    1 PLINTH"), "{f}:9:26-30: field MAT of ELEMENTS 1: expected a solid material: PJOINT is the law of joints, given on INTERFACE cards, found '2'"),
]
# The slab concrete's tensile strength (issue 22): ELASTIC FT.
cases += [
 ("elastic-ft-negative", sub("   20000.0       0.3      20.0", "   20000.0       0.3      20.0   -2000.0"), "{f}:12:31-40: field FT of MATERIALS 1: expected a real >= 0 (kPa), found '-2000.0'"),
]
# The error control of midpoint and Euler increments (issue 21): CONTROL's ERRCTL card.
counts = "    6    2    1\n"
cases += [
 ("errctl-negative", sub(counts, counts + "ERRCTL         -0.01\n"), "{f}:5:11-20: field ERRTOL of CONTROL ERRCTL: expected a real with 0 <= ERRTOL <= 1 (0: no error control), found '-0.01'"),
 ("errctl-word", sub(counts, counts + "ERRCTL         0.5 %\n"), "{f}:5:11-20: field ERRTOL of CONTROL ERRCTL: expected a real number, found '0.5 %'"),
 ("errctl-depth", sub(counts, counts + "ERRCTL         0.005   21\n"), "{f}:5:21-25: field DEPTH of CONTROL ERRCTL: expected a number of halvings with 0 <= DEPTH <= 20, found '21'"),
 ("errctl-twice", sub(counts, counts + "ERRCTL\nERRCTL         0.01\n"), "{f}:6: CONTROL takes one ERRCTL card (the first is at line 5)"),
]
# The contact pair's roles (issue 20): PAIR field ROLES.
cases += [
 ("contact-roles", csub(CPAIR, CPAIR.ljust(75) + "BOTH"), "{f}:17:76-80: field ROLES of CONTACT PAIR TOP: expected AUTO (a much finer slave becomes the master) or ASIS, found 'BOTH'"),
]
for old in os.listdir(P):
    os.remove(P + old)
for i, (name, deck, expect) in enumerate(cases, 1):
    f = f"{P}{i:02d}-{name}.dat"
    with open(f, "w") as h:
        h.write("* expect: " + expect.format(f=f) + "\n" + deck)
print(len(cases))
