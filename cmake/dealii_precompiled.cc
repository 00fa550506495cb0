// The host of the precompiled deal.II headers (cmake/dealii_precompiled.h); no code.
