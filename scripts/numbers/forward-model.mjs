// The forward beam model of Table 6.1 at the chapter's reference setting
// (z_hit 0.8, sigma_hit 0.15 m, z_short 0.1, lambda_short 1/m, z_max weight
// 0.05, z_rand 0.05, z_max 3 m): p(z = 2 | z* = 2) and p(z = 2 | z* = 3).
export default async function (core) {
  return {
    forwardModel: {
      pZ2GivenZstar2: core.forwardDensity(2, 2, undefined),
      pZ2GivenZstar3: core.forwardDensity(2, 3, undefined),
    },
  };
}
