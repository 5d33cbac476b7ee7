% Metrics of a map onto an ellipsoid, computed the same way for demkit's
% output and for the reference's (same faces and vertex order as the input):
%
%   octave-cli ellipsoid_metrics.m MESH.obj POP MAP.obj A:B:C [ALPHA]
%
% POP: a population file or 'area'. A:B:C: the radii the map lies on (for
% EDEQ, the radii it chose). Prints one line:
%   ELLIPSOID face_density_var_final=... density_error_mean=... mean_abs_mu=...
%             flipped=... residual=... energy=...
% face_density_var_final: Var(rho_F / mean rho_F), rho_F = P ./ A (the
%   demos' var(density/mean(density), 1));
% mean_abs_mu: mean over faces of |mu| of the map from the input surface;
% flipped: faces with ((b-a) x (c-a)) . (a+b+c) <= 0;
% residual: max over vertices of |x^2/A^2 + y^2/B^2 + z^2/C^2 - 1|;
% energy (with ALPHA, default 5): EDEQ's objective on this map and radii,
%   sum over vertices of |grad rho~ / max rho_V|^2 + ALPHA sum over faces of
%   |mu|^2, rho~ the vertex density after one backward-Euler diffusion step
%   of length 0.1 on the map (as ellipsoid_energy.m says).
args = argv();
addpath(fileparts(mfilename('fullpath')));
[v, f] = read_obj(args{1});
[map, g] = read_obj(args{3});
if ~isequal(f, g) || size(v, 1) ~= size(map, 1)
  error('%s does not have the faces of %s', args{3}, args{1});
end
radii = sscanf(strrep(args{4}, ':', ' '), '%f').';
alpha = 5;
if numel(args) >= 5, alpha = str2double(args{5}); end
if strcmp(args{2}, 'area')
  population = triangle_areas(v, f);
else
  population = sscanf(regexprep(fileread(args{2}), '#[^\n]*', ''), '%f');
end
m = density_metrics(f, population, map, 'sphere');
mu = abs(beltrami_of_map(v, map, f));
q = map(:, 1) .^ 2 / radii(1) ^ 2 + map(:, 2) .^ 2 / radii(2) ^ 2 + map(:, 3) .^ 2 / radii(3) ^ 2;
[e_density, e_mu] = ellipsoid_energy(v, f, population, map, 0.1);
printf('ELLIPSOID face_density_var_final=%.6g density_error_mean=%.6g mean_abs_mu=%.6g flipped=%d residual=%.3g energy=%.6g energy_density=%.6g energy_mu=%.6g\n', ...
       m.face_density_var_final, m.density_error_mean, mean(mu), m.flipped, max(abs(q - 1)), ...
       e_density + alpha * e_mu, e_density, e_mu);
