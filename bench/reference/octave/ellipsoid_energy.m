function [e_density, e_mu] = ellipsoid_energy(v, f, population, map, dt)
% The two terms of EDEQ's objective for the map `map` of the surface (v, f):
%   e_density = sum over vertices of |grad rho~(v)|^2 / (max rho_V)^2, where
%     rho_F = P / A on the map, rho_V its area-weighted average at the
%     vertices, rho~ solves (M + dt L) rho~ = M rho_V (M the lumped mass, L
%     the cotangent Laplacian of the map), grad rho~ per face averaged to the
%     vertices with the face areas as weights;
%   e_mu = sum over faces of |mu|^2, mu of the map from the input surface.
% The objective is e_density + alpha e_mu.
nv = size(map, 1);
A = triangle_areas(map, f);
rho_f = population(:) ./ A;
w = accumarray(f(:), repmat(A, 3, 1), [nv 1]);
rho_v = accumarray(f(:), repmat(A .* rho_f, 3, 1), [nv 1]) ./ w;
% Cotangent Laplacian and lumped mass of the map.
L = sparse(nv, nv);
for k = 1:3
  i = f(:, k); j = f(:, mod(k, 3) + 1); o = f(:, mod(k + 1, 3) + 1);
  u = map(i, :) - map(o, :); t = map(j, :) - map(o, :);
  cot_o = sum(u .* t, 2) ./ sqrt(sum(cross(u, t, 2) .^ 2, 2));
  L = L + sparse([i; j; i; j], [j; i; i; j], 0.5 * [-cot_o; -cot_o; cot_o; cot_o], nv, nv);
end
M = sparse(1:nv, 1:nv, w / 3);
rho = (M + dt * L) \ (M * rho_v);
% Per-face gradient of the linear interpolant of rho.
p1 = map(f(:, 1), :); p2 = map(f(:, 2), :); p3 = map(f(:, 3), :);
n = cross(p2 - p1, p3 - p1, 2);
n2 = sum(n .^ 2, 2);
g = (cross(n, p3 - p2, 2) .* rho(f(:, 1)) + cross(n, p1 - p3, 2) .* rho(f(:, 2)) ...
     + cross(n, p2 - p1, 2) .* rho(f(:, 3))) ./ n2;
gv = zeros(nv, 3);
for d = 1:3
  gv(:, d) = accumarray(f(:), repmat(A .* g(:, d), 3, 1), [nv 1]) ./ w;
end
e_density = sum(sum((gv / max(rho_v)) .^ 2));
e_mu = sum(abs(beltrami_of_map(v, map, f)) .^ 2);
end
