#include "multibody/data.h"

namespace plantar::multibody {

Data::Data(const Model& model)
    : liMi(model.n_bodies), oMi(model.n_bodies), v(model.n_bodies, Vector6d::Zero()),
      a(model.n_bodies, Vector6d::Zero()), f(model.n_bodies, Vector6d::Zero()),
      composite(model.n_bodies), mass_matrix(Eigen::MatrixXd::Zero(model.nv, model.nv)),
      tau(Eigen::VectorXd::Zero(model.nv)), bias(Eigen::VectorXd::Zero(model.nv)),
      zero_nv(Eigen::VectorXd::Zero(model.nv)), com_jacobian(Eigen::Matrix3Xd::Zero(3, model.nv)),
      jacobian(Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, model.nv)) {}

} // namespace plantar::multibody
