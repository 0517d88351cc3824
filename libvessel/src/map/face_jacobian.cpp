#include "detail/face_jacobian.h"

namespace vessel::detail {

FaceOperator face_operator(const Eigen::Vector3d& q0, const Eigen::Vector3d& q1,
                           const Eigen::Vector3d& q2, const std::array<int, 3>& corner)
{
    FaceOperator op;
    op.corner = corner;
    const Eigen::Vector3d e1 = q1 - q0;
    const Eigen::Vector3d e2 = q2 - q0;
    const Eigen::Vector3d ax = e1.normalized();
    const Eigen::Vector3d ay = (e2 - e2.dot(ax) * ax).normalized();
    Eigen::Matrix2d P;  // columns: the two edges in a local orthonormal frame
    P << e1.dot(ax), e2.dot(ax), 0.0, e2.dot(ay);
    const Eigen::Matrix2d Pi = P.inverse();
    op.d0 = {-(Pi(0, 0) + Pi(1, 0)), Pi(0, 0), Pi(1, 0)};
    op.d1 = {-(Pi(0, 1) + Pi(1, 1)), Pi(0, 1), Pi(1, 1)};
    op.area = 0.5 * std::abs(P.determinant());
    return op;
}

std::vector<FaceOperator> face_operators(const Mesh& mesh)
{
    std::vector<FaceOperator> ops(mesh.n_faces());
    for (auto f : mesh.faces())
    {
        auto h = f.halfedge();
        ops[f.idx()] = face_operator(to_eigen(mesh.point(h.from())), to_eigen(mesh.point(h.to())),
                                     to_eigen(mesh.point(h.next().to())),
                                     {h.from().idx(), h.to().idx(), h.next().to().idx()});
    }
    return ops;
}

}  // namespace vessel::detail
