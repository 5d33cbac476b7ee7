function m = density_metrics(f, population, map, domain)
% The density metrics of a map, defined as demkit's report defines them
% (DESIGN.md "Report", crates/demkit/src/metrics.rs), computed the same way
% for demkit's output and for the reference's:
%   A(T)  area of the flat triangle between the mapped corners of face T
%         (on the sphere; on the torus in R^3 for a toroidal map),
%   P(T)  the face population,
%   d(T)  = log((A(T)/sum A) / (P(T)/sum P)),
%   density_error_mean / _sd = mean / population sd of |d(T)|,
%   face_density_var_final   = Var(rho_F / mean rho_F), rho_F = P./A,
%   density_var_final        = Var(rho_V / mean rho_V), rho_V = W^FV rho_F
%                              (area-weighted average over each vertex's faces),
%   flipped (domain 'sphere') = faces with ((b-a) x (c-a)) . (a+b+c) <= 0.
% Variances are population variances (divided by n).
population = population(:);
a = map(f(:, 1), :); b = map(f(:, 2), :); c = map(f(:, 3), :);
n = cross(b - a, c - a, 2);
A = 0.5 * sqrt(sum(n .^ 2, 2));
d = abs(log((A / sum(A)) ./ (population / sum(population))));
m.density_error_mean = mean(d);
m.density_error_sd = sqrt(mean((d - mean(d)) .^ 2));
rho_f = population ./ A;
nv = size(map, 1);
s = accumarray(f(:), repmat(A .* rho_f, 3, 1), [nv 1]);
w = accumarray(f(:), repmat(A, 3, 1), [nv 1]);
rho_v = s ./ w;
rho_v(w == 0) = 0;
m.density_var_final = normalized_variance(rho_v);
m.face_density_var_final = normalized_variance(rho_f);
if strcmp(domain, 'sphere')
  m.flipped = sum(sum(n .* (a + b + c), 2) <= 0);
else
  m.flipped = NaN;   % toroidal flips are counted on the periodic planar image; not here
end
end

function v = normalized_variance(x)
x = x / mean(x);
v = mean((x - 1) .^ 2);
end
