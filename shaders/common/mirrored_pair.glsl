// The mirrored pair of Guertin et al. 2014 (docs/spec.md §7.2), shared by the filters that
// take it: the pair takes the weight of its sample that is nearer and moves farther (sample
// 1's where neither sample is both). z: depths, s: speeds of samples 1 and 2.
void mirror_pair(inout float a1, inout float a2, float z1, float z2, float s1, float s2) {
    bool behind = z1 > z2;
    bool slower = s2 > s1;
    if (behind && slower) a1 = a2;
    else if (!behind && !slower) a2 = a1;
}
