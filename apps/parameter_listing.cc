#include "apps/parameter_listing.h"

#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>

#include <sstream>
#include <string>

namespace plantar::app {
namespace {

// deal.II mangles names in its XML output: every character that is not a
// letter or digit becomes '_' followed by two hex digits.
std::string demangle(const std::string& name) {
  std::string out;
  for (std::size_t i = 0; i < name.size(); ++i)
    if (name[i] == '_' && i + 2 < name.size()) {
      out += static_cast<char>(std::stoi(name.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else
      out += name[i];
  return out;
}

void print_tree(const boost::property_tree::ptree& tree, const std::string& indent,
                std::ostream& out) {
  for (const auto& [key, child] : tree) {
    if (key == "<xmlattr>")
      continue;
    const std::string name = demangle(key);
    if (child.count("value")) {
      out << indent << name << " = " << child.get<std::string>("default_value") << "\n"
          << indent << "    allowed: " << child.get<std::string>("pattern_description") << "\n";
      const std::string doc = child.get<std::string>("documentation", "");
      if (!doc.empty())
        out << indent << "    " << doc << "\n";
    } else {
      out << indent << "subsection " << name << "\n";
      print_tree(child, indent + "  ", out);
      out << indent << "end\n";
    }
  }
}

} // namespace

void print_parameter_listing(const dealii::ParameterHandler& prm, std::ostream& out) {
  std::stringstream xml;
  prm.print_parameters(xml, dealii::ParameterHandler::XML);
  boost::property_tree::ptree tree;
  boost::property_tree::read_xml(xml, tree);
  out << "Scene parameters (name = default, allowed values, meaning):\n\n";
  print_tree(tree.get_child("ParameterHandler"), "", out);
}

} // namespace plantar::app
