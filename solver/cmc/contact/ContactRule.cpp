#include "cmc/contact/ContactRule.hpp"

namespace cmc {

namespace {
// count (over all ranks) over the number of entries of a field of which this rank holds n.
double fraction(std::size_t count, std::size_t n) {
  const std::size_t total = Grid::total(n);
  return total ? double(count) / double(total) : 0.0;
}
}  // namespace

std::size_t contact_points(const Field& gap, const ContactRule& rule) {
  return Grid::count_if(gap, [&](double g) { return rule.in_contact(g); });
}
double contact_fraction(const Field& gap, const ContactRule& rule) { return fraction(contact_points(gap, rule), gap.size()); }
double repulsive_fraction(const Field& pressure, const ContactRule& rule) {
  return fraction(Grid::count_if(pressure, [&](double p) { return rule.repulsive(p); }), pressure.size());
}
double attractive_fraction(const Field& pressure, const ContactRule& rule) {
  return fraction(Grid::count_if(pressure, [&](double p) { return rule.attractive(p); }), pressure.size());
}

Mask contact_mask(const Field& gap, const ContactRule& rule) {
  Mask m(gap.size());
  Grid::parallel_for(gap.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) m[k] = rule.in_contact(gap[k]);
  });
  return m;
}

double mask_fraction(const Mask& mask) { return fraction(Grid::count(mask), mask.size()); }

}  // namespace cmc
