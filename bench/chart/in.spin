# Rigid rotation of a free block (bench/chart, scene "spin"): after the
# families are built, the body is turned rigidly by th degrees about z
# through its centre; an objective model gives zero energy and force.  Prints
# the energy density sum and the RMS force density for each angle.
# Variables: n, dim, pstyle, pcoeff
variable        dx equal 0.001
units           si
dimension       ${dim}
atom_style      peri
atom_modify     map array
if "${dim} == 3" then "boundary s s s" "lattice sc ${dx}" "region box block -0.25 $(v_n-0.75) -0.25 $(v_n-0.75) -0.25 $(v_n-0.75)" &
else "boundary s s p" "lattice sq ${dx}" "region box block -0.25 $(v_n-0.75) -0.25 $(v_n-0.75) -0.5 0.5"
create_box      1 box
create_atoms    1 box
set             group all density 7850
set             group all volume $(v_dx^3)
neighbor        $(0.3*v_dx) bin
pair_style      ${pstyle}
pair_coeff      ${pcoeff}
thermo_modify   norm no
run             0
variable        cx equal $(xcm(all,x))
variable        cy equal $(xcm(all,y))
variable        cz equal $(xcm(all,z))
variable        f2 atom fx*fx+fy*fy+fz*fz
compute         f2 all reduce ave v_f2
thermo_style    custom step pe c_f2
variable        th index 1 3 10 30 60 90
label           loop
displace_atoms  all rotate ${cx} ${cy} ${cz} 0 0 1 ${th} units box
run             0
print           "SPIN ${th} pe $(pe) frms $(sqrt(c_f2)) natoms $(atoms)"
displace_atoms  all rotate ${cx} ${cy} ${cz} 0 0 1 -${th} units box
next            th
jump            SELF loop
