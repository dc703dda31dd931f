#!/bin/sh
# All FEM references of the shear-surface study: regenerates ../results/fem_reactions.jsonl
# (about 3 min on 2 cores) and ../results/profile_nu*.json (about 1 min).
# The domain [a, b] is the innermost constrained point centres of each PD run (see pd.py).
set -ex
cd "$(dirname "$0")"
: > ../results/fem_reactions.jsonl
# the original sequence: reproduces ../../fem/reference.json's reaction 1.4093043e-5
python3 fem_reaction.py --hs 0.01,0.005,0.0025,0.00125 --tag check_orig
P="python3 fem_reaction.py --hs 0.005,0.0025"
for nu in 0.3333333333333333 0.0; do
  $P --nu $nu --a 0.025 --b 0.9725 --tag r1
  $P --nu $nu --a 0.0275 --b 0.97125 --tag r2
  $P --nu $nu --a 0.028333333333333335 --b 0.9708333333333334 --tag r3
  $P --nu $nu --a 0.02875 --b 0.9706250000000001 --tag r4
  $P --nu $nu --e2 1.0 --a 0.025 --b 0.9750000000000001 --tag single_u0.01
  $P --nu $nu --e2 1.0 --a 0.0275 --b 0.9725 --tag single_u0.005
  $P --nu $nu --a 0.025 --b 0.9725 --H 0.2 --tag r1_H0.2
  $P --nu $nu --a 0.025 --b 0.9725 --H 0.4 --tag r1_H0.4
  $P --nu $nu --a 0.025 --b 0.9725 --roller --tag r1_roller
done
python3 fem_profile.py 0.3333333333333333
python3 fem_profile.py 0.0
