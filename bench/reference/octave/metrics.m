% Density metrics of a map OBJ (same faces and vertex order as the input),
% computed by density_metrics.m for demkit's output and the reference's alike.
%
%   octave-cli metrics.m MESH.obj POP MAP.obj sphere|torus [REPORT.json]
%
% POP: a population file or 'area' (the input's face areas).
% Prints: METRICS density_error_mean=... density_error_sd=...
%         density_var_final=... face_density_var_final=... flipped=...
% and, given demkit's report of the map, what it says (for a cross-check):
%         REPORT iterations=... total_s=... density_error_mean=...
%         density_var_final=... flipped=... converged=...
args = argv();
addpath(fileparts(mfilename('fullpath')));
[v, f] = read_obj(args{1});
[map, g] = read_obj(args{3});
if ~isequal(f, g) || size(v, 1) ~= size(map, 1)
  error('%s does not have the faces of %s', args{3}, args{1});
end
if strcmp(args{2}, 'area')
  n = cross(v(f(:, 2), :) - v(f(:, 1), :), v(f(:, 3), :) - v(f(:, 1), :), 2);
  population = 0.5 * sqrt(sum(n .^ 2, 2));
else
  population = sscanf(regexprep(fileread(args{2}), '#[^\n]*', ''), '%f');
end
m = density_metrics(f, population, map, args{4});
printf('METRICS density_error_mean=%.6g density_error_sd=%.6g density_var_final=%.6g face_density_var_final=%.6g flipped=%g\n', ...
       m.density_error_mean, m.density_error_sd, m.density_var_final, m.face_density_var_final, m.flipped);
if numel(args) >= 5
  r = jsondecode(fileread(args{5}));
  printf('REPORT iterations=%d total_s=%.6f density_error_mean=%.6g density_var_final=%.6g flipped=%d converged=%d\n', ...
         r.iterations, r.time_s.total, r.metrics.density_error_mean, r.metrics.density_var_final, ...
         r.metrics.flipped_triangles, r.converged);
end
