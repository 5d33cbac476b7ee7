function [x, fval, exitflag, output] = fmincon(fun, x0, A, b, Aeq, beq, lb, ub, nonlcon, options)
% Stand-in for MATLAB's fmincon (Optimization Toolbox), which Octave lacks.
% Supports only what the reference code uses: a smooth-enough objective with
% bound constraints lb <= x <= ub (no linear or nonlinear constraints).
% Solved with Octave's own sqp (BFGS-updated SQP, finite-difference gradient);
% MATLAB's default is an interior-point method, so iterates and the optimum
% found can differ slightly from MATLAB's.
if nargin >= 3 && ~isempty(A) || nargin >= 5 && ~isempty(Aeq) || nargin >= 9 && ~isempty(nonlcon)
  error('fmincon stand-in: only bound constraints are supported');
end
if nargin < 7, lb = []; end
if nargin < 8, ub = []; end
maxiter = 1000;                       % MATLAB's default MaxIterations for fmincon
if nargin >= 10 && isstruct(options) && isfield(options, 'MaxIterations')
  maxiter = options.MaxIterations;
end
shape = size(x0);
f = @(y) fun(reshape(y, shape));
[y, fval, info, iter, nf] = sqp(x0(:), f, [], [], lb(:), ub(:), maxiter);
x = reshape(y, shape);
exitflag = double(info == 101 || info == 104);
output = struct('iterations', iter, 'funcCount', nf, 'sqp_info', info);
end
